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
#       VARIANT debug: D8 with dependency jars pre-dexed once (cached by content hash), the resources
#       linked with android:debuggable="true" (as the Android Gradle Plugin's debug build type);
#       VARIANT release: R8 shrinking with aapt2's keep rules, app/proguard-rules.pro, the libraries'
#       consumer rules (LIBRARY_RULES) and the rules jars embed for R8 (META-INF/com.android.tools);
#       it refuses to sign with the debug key or without a key.
#       Then package (with the jars' Java resources, as AGP packages them), zipalign, apksigner sign
#       (v2 and v3, as app/build.gradle.kts declares) and verify: TARGET_DIR/motion-fusion-VARIANT.apk
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
        [ -f "$jar" ] || continue
        # The manifest left out only where there is one (unzip prints a caution for an exclusion that matches nothing).
        if unzip -Z1 "$jar" META-INF/MANIFEST.MF >/dev/null 2>&1; then
          unzip -qqo "$jar" -d "$target/classes" -x 'META-INF/MANIFEST.MF'
        else
          unzip -qqo "$jar" -d "$target/classes"
        fi
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
  local quiet=(-e "Unknown chunk type '200'" -e "unexpected element <property> found in <manifest><application><service>")
  rm -f "$out/resources-debug.ap_"
  aapt2 link -o "$out/resources.ap_" -I "$android_jar" --manifest "$manifest" --warn-manifest-validation \
    --java "$gen" --proguard "$out/aapt-rules.pro" --output-text-symbols "$out/R.txt" --emit-ids "$out/ids.txt" \
    --auto-add-overlay "${overlays[@]}" -R "$out/compiled.zip" 2>&1 \
    | { grep -v "${quiet[@]}" || true; } >&2
  [ -f "$out/resources.ap_" ] || die "aapt2 link failed"
  # The debug APK's: the same resources with the same ids, android:debuggable="true" added to
  # <application> as the Android Gradle Plugin's debug build type does (the release APK and
  # Robolectric keep the manifest as written).
  aapt2 link -o "$out/resources-debug.ap_" -I "$android_jar" --manifest "$manifest" --warn-manifest-validation \
    --debug-mode --stable-ids "$out/ids.txt" \
    --auto-add-overlay "${overlays[@]}" -R "$out/compiled.zip" 2>&1 \
    | { grep -v "${quiet[@]}" || true; } >&2
  [ -f "$out/resources-debug.ap_" ] || die "aapt2 link (debug) failed"
  app_pkg=$(grep -o 'package="[^"]*"' "$manifest" | head -1 | cut -d'"' -f2)
  while read -r dir pkg; do
    if [ -s "$dir/R.txt" ] && [ "$pkg" != "$app_pkg" ]; then library_r "$out/R.txt" "$dir/R.txt" "$pkg" "$gen"; fi
  done < "$libraries"
}

# The Android Gradle Plugin 8.7's default packaging excludes (PackagingOptionsUtils' defaultExcludes in
# com.android.tools.build:gradle:8.7.3; MavenApkTest reads them from that jar and checks the APK):
# globs over the archive path with a leading /, ** any folders, * within one.
AGP_EXCLUDES='/META-INF/LICENSE
/META-INF/LICENSE.txt
/META-INF/MANIFEST.MF
/META-INF/NOTICE
/META-INF/NOTICE.txt
/META-INF/*.DSA
/META-INF/*.EC
/META-INF/*.SF
/META-INF/*.RSA
/META-INF/maven/**
/META-INF/proguard/*
/META-INF/com.android.tools/**
/NOTICE
/NOTICE.txt
/LICENSE.txt
/LICENSE
**/.svn/**
**/CVS/**
**/SCCS/**
**/.*/**
**/.*
**/*~
**/thumbs.db
**/picasa.ini
**/about.html
**/package.html
**/overview.html
**/protobuf.meta
**/_*
**/_*/**
**/*.kotlin_metadata'

# The Java resources of the given jars into OUT, as AGP merges them: every file that is not a class,
# less AGP_EXCLUDES; META-INF/services/* of several jars concatenated; any other path found in two
# jars with different content stops the build, as it stops AGP's. A Kotlin Multiplatform library's
# root artifact (its common metadata, no classes: META-INF/kotlin-project-structure-metadata.json) is
# skipped: Maven puts it on the class path beside the -jvm jar, Gradle resolves only the latter.
java_resources() {
  local out=$1; shift
  local tmp="$out.jars" i=0 jar
  rm -rf "$out" "$tmp"; mkdir -p "$out" "$tmp"
  for jar in "$@"; do
    i=$((i + 1))
    if unzip -l "$jar" META-INF/kotlin-project-structure-metadata.json >/dev/null 2>&1; then continue; fi
    mkdir -p "$tmp/$i"
    unzip -qqo "$jar" -d "$tmp/$i" -x '*.class' 2>/dev/null || [ $? -eq 11 ] || die "cannot read $jar"
    echo "$i $jar"
  done > "$tmp/jars.txt"
  (cd "$tmp" && find . -mindepth 2 -type f | sort -t/ -k2,2n -k3) \
    | EXCLUDES="$AGP_EXCLUDES" perl -e '
      my ($out, $tmp) = @ARGV;
      my %jar;
      open my $list, "<", "$tmp/jars.txt" or die; while (<$list>) { chomp; my ($k, $v) = split / /, $_, 2; $jar{$k} = $v } close $list;
      my @ex;
      for my $g (grep { length } split /\n/, $ENV{EXCLUDES}) {
        $g = "/$g" unless $g =~ m{^[/*]};
        my $r = join "", map { $_ eq "**" ? ".*" : $_ eq "*" ? "[^/]*" : $_ eq "?" ? "[^/]" : quotemeta $_ } split /(\*\*|\*|\?)/, $g;
        push @ex, qr/^$r$/;
      }
      sub slurp { my $f = shift; open my $in, "<:raw", $f or die "$f: $!"; local $/; my $d = <$in>; close $in; defined $d ? $d : "" }
      my %from;
      while (my $line = <STDIN>) {
        chomp $line;
        my ($n, $path) = $line =~ m{^\./(\d+)/(.*)$} or next;
        next if grep { "/$path" =~ $_ } @ex;
        my $data = slurp("$tmp/$n/$path");
        my $dest = "$out/$path";
        (my $dir = $dest) =~ s{/[^/]*$}{};
        system("mkdir", "-p", $dir) == 0 or die;
        if (exists $from{$path}) {
          my $have = slurp($dest);
          if ($path =~ m{^META-INF/services/}) {
            open my $o, ">>:raw", $dest or die;
            print $o "\n" if length $have && $have !~ /\n\z/;
            print $o $data;
            close $o;
            next;
          }
          next if $have eq $data;
          die "android-build: 2 files found with path $path ($jar{$from{$path}} and $jar{$n}); AGP stops on it too: exclude or pick one in both builds\n";
        }
        open my $o, ">:raw", $dest or die; print $o $data; close $o;
        $from{$path} = $n;
      }' "$out" "$tmp"
  rm -rf "$tmp"
}

# The keep rules the jars embed, as AGP picks them for R8 VERSION: a jar with META-INF/com.android.tools/
# gives the files of its r8, r8-from-V, r8-upto-V and r8-from-V-upto-V folders whose range holds
# VERSION (from inclusive, upto exclusive); a jar without gives META-INF/proguard/*. One file per rule
# set in OUT.
version_ge() { [ "$(printf '%s\n%s\n' "$2" "$1" | sort -V | head -1)" = "$2" ]; }
jar_rules() {
  local version=$1 out=$2; shift 2
  local jar entry dir from upto i=0
  rm -rf "$out"; mkdir -p "$out"
  for jar in "$@"; do
    i=$((i + 1))
    local -a entries=()
    mapfile -t entries < <(unzip -Z1 "$jar" 2>/dev/null | grep -E '^META-INF/(com\.android\.tools|proguard)/.*[^/]$' || true)
    [ ${#entries[@]} -gt 0 ] || continue
    if grep -q '^META-INF/com\.android\.tools/' <<< "$(printf '%s\n' "${entries[@]}")"; then
      for entry in "${entries[@]}"; do
        [[ $entry =~ ^META-INF/com\.android\.tools/(r8[^/]*)/[^/]+$ ]] || continue
        dir=${BASH_REMATCH[1]}
        [[ $dir =~ ^r8(-from-([0-9.]+))?(-upto-([0-9.]+))?$ ]] || continue
        from=${BASH_REMATCH[2]}; upto=${BASH_REMATCH[4]}
        if [ -n "$from" ] && ! version_ge "$version" "$from"; then continue; fi
        if [ -n "$upto" ] && version_ge "$version" "$upto"; then continue; fi
        unzip -p "$jar" "$entry" > "$out/$i-$(basename "$jar" .jar)-$dir-$(basename "$entry")"
      done
    else
      for entry in "${entries[@]}"; do
        [[ $entry =~ ^META-INF/proguard/[^/]+$ ]] || continue
        unzip -p "$jar" "$entry" > "$out/$i-$(basename "$jar" .jar)-proguard-$(basename "$entry")"
      done
    fi
  done
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

  # The app's own classes (Kotlin, R) and Java resources as one jar.
  (cd "$target/classes" && zip -qr "$work/app-classes.jar" .)
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
        # The libraries' own notes (D8 stripping locals tables they ship inconsistent) are infos about
        # code that is not ours: not shown. Their warnings and errors still are.
        $d8 com.android.tools.r8.D8 --debug --intermediate --min-api 26 --map-diagnostics info none \
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
    local r8_version
    r8_version=$(java -cp "$r8" com.android.tools.r8.R8 --version | awk 'NR == 1 { print $2 }')
    jar_rules "$r8_version" "$work/jar-rules" "${deps[@]}"
    local -a jar_confs=()
    for f in "$work/jar-rules"/*; do [ -f "$f" ] && jar_confs+=(--pg-conf "$f"); done
    java -Xmx3g -cp "$r8" com.android.tools.r8.R8 --release --min-api 26 \
      --lib "$android_jar" --lib "$jdk" \
      --pg-conf "$target/aapt/aapt-rules.pro" --pg-conf "$target/../proguard-rules.pro" \
      --pg-conf "$library_rules" "${jar_confs[@]}" \
      --pg-map-output "$work/mapping.txt" --output "$work/dex" \
      "$work/app-classes.jar" "${deps[@]}"
  fi

  # The jars' Java resources: ServiceLoader entries (kotlinx-coroutines finds Dispatchers.Main through
  # them), Kotlin's module and builtins files, version files, coroutines' DebugProbesKt.bin.
  java_resources "$work/meta" "$work/app-classes.jar" "${deps[@]}"

  local unaligned="$work/unaligned.apk" apk="$target/motion-fusion-$variant.apk"
  local resources="$target/aapt/resources.ap_"
  if [ "$variant" = debug ]; then resources="$target/aapt/resources-debug.ap_"; fi
  [ -f "$resources" ] || die "$resources missing: run the resources step first"
  cp "$resources" "$unaligned"
  (cd "$work/dex" && zip -q "$unaligned" classes*.dex)
  if [ -n "$(ls -A "$work/meta")" ]; then (cd "$work/meta" && zip -qr "$unaligned" .); fi
  zipalign -p -f 4 "$unaligned" "$work/aligned.apk"
  apksigner sign --v1-signing-enabled false --v2-signing-enabled true --v3-signing-enabled true --v4-signing-enabled false \
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
