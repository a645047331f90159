#!/usr/bin/env bash
# Android build steps without Gradle, called by app/pom.xml:
#   resources ANDROID_JAR MANIFEST RES_DIR OUT_DIR GEN_DIR
#       aapt2 compile + link: OUT_DIR/resources.ap_, OUT_DIR/aapt-rules.pro, R.java in GEN_DIR
#   apk VARIANT ANDROID_JAR R8_JAR TARGET_DIR KEYSTORE PASSWORD ALIAS
#       VARIANT debug: D8 with dependency jars pre-dexed once (cached by content hash);
#       VARIANT release: R8 shrinking with aapt2's keep rules and app/proguard-rules.pro.
#       Then package, zipalign, apksigner sign and verify: TARGET_DIR/motion-fusion-VARIANT.apk
set -euo pipefail

die() { echo "android-build: $*" >&2; exit 1; }
need() { command -v "$1" >/dev/null || die "$1 not found; install it with: apt-get install -y aapt zipalign apksigner zip unzip"; }

java_home() {
  if [ -n "${JAVA_HOME:-}" ]; then echo "$JAVA_HOME"; else dirname "$(dirname "$(readlink -f "$(command -v java)")")"; fi
}

resources() {
  local android_jar=$1 manifest=$2 res=$3 out=$4 gen=$5
  need aapt2
  mkdir -p "$out" "$gen"
  aapt2 compile --dir "$res" -o "$out/compiled.zip"
  # aapt2 prints a harmless "Unknown chunk type '200'" for the API 34 framework resources.
  aapt2 link -o "$out/resources.ap_" -I "$android_jar" --manifest "$manifest" \
    --java "$gen" --proguard "$out/aapt-rules.pro" --auto-add-overlay "$out/compiled.zip" 2>&1 \
    | { grep -v "Unknown chunk type '200'" || true; } >&2
  [ -f "$out/resources.ap_" ] || die "aapt2 link failed"
}

apk() {
  local variant=$1 android_jar=$2 r8=$3 target=$4 keystore=$5 pass=$6 alias=$7
  need zipalign; need apksigner; need zip; need unzip
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
  resources) resources "$@" ;;
  apk) apk "$@" ;;
  *) die "usage: android-build.sh resources|apk ARGS..." ;;
esac
