#!/bin/sh
# Gradle launcher for this project, written instead of the usual wrapper jar: it downloads the
# distribution named by distributionUrl in gradle/wrapper/gradle-wrapper.properties once (checking
# distributionSha256Sum when the file gives one) into ~/.gradle/wrapper/dists and runs it.
set -eu
dir=$(cd "$(dirname "$0")" && pwd)
props="$dir/gradle/wrapper/gradle-wrapper.properties"
[ -f "$props" ] || { echo "gradlew: $props not found" >&2; exit 1; }
prop() { sed -n "s/^$1=//p" "$props" | sed 's/\\:/:/g' | tail -n 1; }
url=$(prop distributionUrl)
sum=$(prop distributionSha256Sum)
[ -n "$url" ] || { echo "gradlew: no distributionUrl in $props" >&2; exit 1; }
zip_name=$(basename "$url")
name=${zip_name%.zip}
home="${GRADLE_USER_HOME:-$HOME/.gradle}/wrapper/dists/$name"
gradle_dir="$home/${name%-bin}"
gradle_dir="${gradle_dir%-all}"
if [ ! -x "$gradle_dir/bin/gradle" ]; then
  mkdir -p "$home"
  tmp="$home/$zip_name.part"
  echo "Downloading $url" >&2
  if command -v curl >/dev/null 2>&1; then curl -fL --retry 3 -o "$tmp" "$url"
  elif command -v wget >/dev/null 2>&1; then wget -O "$tmp" "$url"
  else echo "gradlew: curl or wget is needed to download $url" >&2; exit 1; fi
  if [ -n "$sum" ]; then
    echo "$sum  $tmp" | sha256sum -c - >/dev/null || { echo "gradlew: $zip_name does not match distributionSha256Sum" >&2; rm -f "$tmp"; exit 1; }
  fi
  command -v unzip >/dev/null 2>&1 || { echo "gradlew: unzip is needed" >&2; exit 1; }
  unzip -q -o "$tmp" -d "$home"
  rm -f "$tmp"
fi
exec "$gradle_dir/bin/gradle" -p "$dir" "$@"
