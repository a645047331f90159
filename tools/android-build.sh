#!/usr/bin/env bash
# Android build steps without Gradle, called by the poms of android-libs, android-test-libs and app:
#   libraries AAR_LIST TARGET_DIR
#       unpacks each AAR of the colon-separated AAR_LIST (in that order) under TARGET_DIR/aar/, compiles its
#       resources with aapt2, merges its classes.jar and libs/*.jar into TARGET_DIR/classes and lists
#       "folder package" per library in TARGET_DIR/aar/libraries.txt (done once per AAR until a clean)
#   manifest SOURCE OUT PACKAGE VERSION_CODE VERSION_NAME MIN_SDK TARGET_SDK
#       the app's manifest with what the Android Gradle Plugin adds from build.gradle.kts: package,
#       versionCode, versionName, <uses-sdk>, and ${applicationId} replaced by PACKAGE
#   resources ANDROID_JAR MANIFEST RES_DIR OUT_DIR GEN_DIR LIBRARIES_TXT
#       aapt2 compile + link of the app's resources over the libraries' (LIBRARIES_TXT as written by
#       "libraries"): OUT_DIR/resources.ap_, OUT_DIR/aapt-rules.pro, OUT_DIR/R.txt; in GEN_DIR the app's
#       R.java and one R.java per library package holding that library's symbols with the app's ids
#   apk VARIANT ANDROID_JAR R8_JAR TARGET_DIR LIBRARY_RULES KEYSTORE PASSWORD ALIAS
#       VARIANT debug: D8 with dependency jars pre-dexed once (cached by content hash);
#       VARIANT release: R8 shrinking with aapt2's keep rules, app/proguard-rules.pro and the libraries'
#       consumer rules (LIBRARY_RULES); it refuses to sign with the debug key or without a key.
#       Then package, zipalign, apksigner sign and verify: TARGET_DIR/motion-fusion-VARIANT.apk
set -euo pipefail

die() { echo "android-build: $*" >&2; exit 1; }
need() { command -v "$1" >/dev/null || die "$1 not found; install it with: apt-get install -y aapt zipalign apksigner zip unzip"; }

java_home() {
  if [ -n "${JAVA_HOME:-}" ]; then echo "$JAVA_HOME"; else dirname "$(dirname "$(readlink -f "$(command -v java)")")"; fi
}

# Debian's aapt2 predates the <macro> resource type (Material 1.12 declares its design tokens with it).
# A macro is only a name for its value, so it is replaced by that value wherever it is referenced
# (all of Material's are ?attr/ references) and the declarations are removed.
expand_macros() {
  local res=$1 table
  [ -d "$res" ] || return 0
  grep -rlq '<macro ' "$res" || return 0
  table=$(grep -rho '<macro name="[^"]*">[^<]*</macro>' "$res" | sed 's/<macro name="\([^"]*\)">\([^<]*\)<\/macro>/\1 \2/')
  grep -rlZ -e '<macro ' -e '@macro/' "$res" | MACROS="$table" xargs -0 perl -i -pe '
    BEGIN { %m = map { split / /, $_, 2 } split /\n/, $ENV{MACROS} }
    s/^\s*<macro name="[^"]*">[^<]*<\/macro>\s*\n//;
    s{\@macro/([\w.]+)}{ exists $m{$1} ? $m{$1} : die "unknown macro $1\n" }ge;'
  ! grep -rq -e '<macro ' -e '@macro/' "$res" || die "$res: macros left after expansion"
}

libraries() {
  local list=$1 target=$2 aar name dir pkg jar
  need aapt2; need unzip
  mkdir -p "$target/aar" "$target/classes"
  local -a aars=()
  IFS=: read -r -a aars < "$list" || true
  : > "$target/aar/libraries.tmp"
  for aar in "${aars[@]}"; do
    name=$(basename "$aar" .aar)
    dir="$target/aar/$name"
    if [ ! -f "$dir/.done" ]; then
      rm -rf "$dir"; mkdir -p "$dir"
      unzip -qo "$aar" -d "$dir"
      expand_macros "$dir/res"
      if [ -d "$dir/res" ] && [ -n "$(ls -A "$dir/res")" ]; then aapt2 compile --dir "$dir/res" -o "$dir/res.zip"; fi
      for jar in "$dir/classes.jar" "$dir"/libs/*.jar; do
        [ -f "$jar" ] && unzip -qqo "$jar" -d "$target/classes" -x 'META-INF/MANIFEST.MF'
      done
      touch "$dir/.done"
    fi
    pkg=$(grep -o 'package="[^"]*"' "$dir/AndroidManifest.xml" | head -1 | cut -d'"' -f2)
    [ -n "$pkg" ] || die "$aar: no package in AndroidManifest.xml"
    echo "$dir $pkg" >> "$target/aar/libraries.tmp"
  done
  mv "$target/aar/libraries.tmp" "$target/aar/libraries.txt"
  # The libraries' consumer ProGuard rules, for R8.
  for aar in "${aars[@]}"; do
    dir="$target/aar/$(basename "$aar" .aar)"
    if [ -f "$dir/proguard.txt" ]; then echo "# $(basename "$dir")"; cat "$dir/proguard.txt"; echo; fi
  done > "$target/aar/consumer-rules.pro"
}

# R.java for one library package: the symbols its R.txt lists, with the values the app's link gave them.
library_r() {
  local app_symbols=$1 lib_symbols=$2 pkg=$3 gen=$4
  local file="$gen/${pkg//.//}/R.java"
  mkdir -p "$(dirname "$file")"
  awk -v pkg="$pkg" '
    NR == FNR { k = $2 " " $3; v = $4; for (i = 5; i <= NF; i++) v = v " " $i; val[k] = v; kind[k] = $1; next }
    { k = $2 " " $3; if (!(k in val)) { missing++; next }
      if (!($2 in seen)) { seen[$2] = 1; types[++n] = $2 }
      body[$2] = body[$2] "      public static " (kind[k] == "int[]" ? "int[] " : "int ") $3 " = " val[k] ";\n" }
    END {
      print "package " pkg ";\n\n/** Generated from the library'"'"'s R.txt with the app'"'"'s resource ids. */\npublic final class R {"
      for (i = 1; i <= n; i++) printf "  public static final class %s {\n%s  }\n", types[i], body[types[i]]
      print "}"
      if (missing) printf "android-build: %s: %d symbols of its R.txt not in the app'"'"'s link\n", pkg, missing > "/dev/stderr"
    }' "$app_symbols" "$lib_symbols" | sed 's/{ \(0x[^}]*\) }/{ \1 }/' > "$file"
}

manifest() {
  local src=$1 out=$2 pkg=$3 code=$4 name=$5 min=$6 target=$7
  local open='<manifest xmlns:android="http://schemas.android.com/apk/res/android">'
  [ "$(grep -cxF "$open" "$src")" = 1 ] || die "$src: expected the line $open"
  grep -q '<uses-sdk\|package=' "$src" && die "$src: package and <uses-sdk> come from the build, not the manifest"
  mkdir -p "$(dirname "$out")"
  awk -v open="$open" -v pkg="$pkg" -v code="$code" -v name="$name" -v min="$min" -v target="$target" '
    $0 == open {
      print "<manifest xmlns:android=\"http://schemas.android.com/apk/res/android\" package=\"" pkg "\""
      print "    android:versionCode=\"" code "\" android:versionName=\"" name "\">"
      print "    <uses-sdk android:minSdkVersion=\"" min "\" android:targetSdkVersion=\"" target "\" />"
      next
    }
    { gsub(/\$\{applicationId\}/, pkg); print }' "$src" > "$out.tmp"
  mv "$out.tmp" "$out"
}

resources() {
  local android_jar=$1 manifest=$2 res=$3 out=$4 gen=$5 libraries=$6 dir pkg app_pkg
  need aapt2
  mkdir -p "$out" "$gen"
  rm -f "$out/resources.ap_"
  aapt2 compile --dir "$res" -o "$out/compiled.zip"
  # Libraries first, in dependency order, then the app: a later overlay overrides an earlier one.
  local -a overlays=()
  while read -r dir pkg; do
    if [ -f "$dir/res.zip" ]; then overlays+=(-R "$dir/res.zip"); fi
  done < "$libraries"
  # aapt2 prints a harmless "Unknown chunk type '200'" for the API 34 framework resources.
  # Debian's aapt2 predates the manifest's <property> element (API 31; the specialUse service's
  # subtype): --warn-manifest-validation makes its "unexpected element" a warning, and the element
  # is kept in the APK as written.
  aapt2 link -o "$out/resources.ap_" -I "$android_jar" --manifest "$manifest" --warn-manifest-validation \
    --java "$gen" --proguard "$out/aapt-rules.pro" --output-text-symbols "$out/R.txt" \
    --auto-add-overlay "${overlays[@]}" -R "$out/compiled.zip" 2>&1 \
    | { grep -v -e "Unknown chunk type '200'" -e "unexpected element <property> found in <manifest><application><service>" || true; } >&2
  [ -f "$out/resources.ap_" ] || die "aapt2 link failed"
  app_pkg=$(grep -o 'package="[^"]*"' "$manifest" | head -1 | cut -d'"' -f2)
  while read -r dir pkg; do
    if [ -s "$dir/R.txt" ] && [ "$pkg" != "$app_pkg" ]; then library_r "$out/R.txt" "$dir/R.txt" "$pkg" "$gen"; fi
  done < "$libraries"
}

apk() {
  local variant=$1 android_jar=$2 r8=$3 target=$4 library_rules=$5 keystore=$6 pass=$7 alias=$8
  need zipalign; need apksigner; need zip; need unzip
  if [ "$variant" = release ]; then
    [ -n "$keystore" ] && [ -n "$alias" ] \
      || die "a release build needs a signing key: mvn -Prelease package -Drelease.keystore=FILE -Drelease.key.alias=ALIAS -Drelease.keystore.password=PASSWORD"
    [ -f "$keystore" ] || die "release keystore $keystore not found"
    [ "$(basename "$keystore")" != debug.keystore ] && [ "$alias" != androiddebugkey ] \
      || die "the debug key signs debug builds only; give the release build its own key (-Drelease.keystore=...)"
  fi
  local work="$target/apk-$variant" jdk
  jdk=$(java_home)
  rm -rf "$work"; mkdir -p "$work/dex" "$work/meta"

  # The app's own classes (Kotlin, R) as one jar.
  (cd "$target/classes" && zip -qr "$work/app-classes.jar" . -x 'META-INF/*.kotlin_module')
  local -a deps=()
  IFS=: read -r -a deps < "$target/runtime-classpath.txt" || true  # no newline at the end

  local d8="java -XX:TieredStopAtLevel=1 -Xmx2g -cp $r8"
  if [ "$variant" = debug ]; then
    local cache="$target/predex" jar key out
    local -a dexed=()
    mkdir -p "$cache"
    for jar in "${deps[@]}"; do
      key="$(basename "$jar" .jar)-$(sha1sum "$jar" | cut -c1-12)"
      out="$cache/$key.zip"
      if [ ! -f "$out" ]; then
        $d8 com.android.tools.r8.D8 --debug --intermediate --min-api 26 \
          --lib "$android_jar" --lib "$jdk" --output "$out.tmp.zip" "$jar"
        mv "$out.tmp.zip" "$out"
      fi
      dexed+=("$out")
    done
    local cp_args=()
    for jar in "${deps[@]}"; do cp_args+=(--classpath "$jar"); done
    $d8 com.android.tools.r8.D8 --debug --intermediate --min-api 26 --lib "$android_jar" --lib "$jdk" \
      "${cp_args[@]}" --output "$work/app-classes.dex.zip" "$work/app-classes.jar"
    $d8 com.android.tools.r8.D8 --debug --min-api 26 --output "$work/dex" \
      "$work/app-classes.dex.zip" "${dexed[@]}"
  else
    java -Xmx3g -cp "$r8" com.android.tools.r8.R8 --release --min-api 26 \
      --lib "$android_jar" --lib "$jdk" \
      --pg-conf "$target/aapt/aapt-rules.pro" --pg-conf "$target/../proguard-rules.pro" \
      --pg-conf "$library_rules" \
      --pg-map-output "$work/mapping.txt" --output "$work/dex" \
      "$work/app-classes.jar" "${deps[@]}"
  fi

  # ServiceLoader entries (kotlinx-coroutines finds Dispatchers.Main through them).
  for jar in "${deps[@]}"; do
    unzip -qo "$jar" 'META-INF/services/*' -d "$work/meta" 2>/dev/null || true
  done

  local unaligned="$work/unaligned.apk" apk="$target/motion-fusion-$variant.apk"
  cp "$target/aapt/resources.ap_" "$unaligned"
  (cd "$work/dex" && zip -q "$unaligned" classes*.dex)
  if [ -d "$work/meta/META-INF" ]; then (cd "$work/meta" && zip -qr "$unaligned" META-INF); fi
  zipalign -p -f 4 "$unaligned" "$work/aligned.apk"
  apksigner sign --v1-signing-enabled false --v4-signing-enabled false \
    --ks "$keystore" --ks-pass "pass:$pass" --ks-key-alias "$alias" \
    --out "$apk" "$work/aligned.apk"
  apksigner verify "$apk"
  echo "android-build: $apk ($(stat -c %s "$apk") bytes)"
}

cmd=${1:-}; shift || true
case "$cmd" in
  manifest) manifest "$@" ;;
  libraries) libraries "$@" ;;
  resources) resources "$@" ;;
  apk) apk "$@" ;;
  *) die "usage: android-build.sh manifest|libraries|resources|apk ARGS..." ;;
esac
