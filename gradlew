#!/bin/sh
# Gradle launcher of this project, a script in place of the usual wrapper jar (none is committed).
# It reads distributionUrl and distributionSha256Sum from gradle/wrapper/gradle-wrapper.properties,
# downloads the distribution once into $GRADLE_USER_HOME/wrapper/dists (default ~/.gradle), refuses
# it unless its SHA-256 is the one given, unpacks it aside and moves it into place only when complete
# (a marker file written last says so; anything without it is removed and fetched again), then runs
# that Gradle with the arguments given, in the current folder, as gradlew does.
set -eu

app_dir=$(cd "$(dirname "$0")" && pwd -P)
props="$app_dir/gradle/wrapper/gradle-wrapper.properties"
die() { echo "gradlew: $*" >&2; exit 1; }
[ -f "$props" ] || die "$props not found"
prop() { sed -n "s/^[[:space:]]*$1[[:space:]]*=[[:space:]]*//p" "$props" | sed 's/\\:/:/g; s/\\=/=/g; s/[[:space:]]*$//' | tail -n 1; }
url=$(prop distributionUrl)
sum=$(prop distributionSha256Sum)
[ -n "$url" ] || die "no distributionUrl in $props"
[ -n "$sum" ] || die "no distributionSha256Sum in $props: the distribution would run unchecked"

zip_name=${url##*/}
dist_name=${zip_name%.zip}
dists="${GRADLE_USER_HOME:-$HOME/.gradle}/wrapper/dists/$dist_name"
home="$dists/script-$sum"
marker="$home/.complete"

sha256() {
  if command -v sha256sum >/dev/null 2>&1; then sha256sum "$1" | cut -d ' ' -f 1
  elif command -v shasum >/dev/null 2>&1; then shasum -a 256 "$1" | cut -d ' ' -f 1
  else die "sha256sum or shasum is needed to check the distribution"; fi
}

install() {
  command -v unzip >/dev/null 2>&1 || die "unzip is needed"
  mkdir -p "$dists"
  tmp_zip=$(mktemp "$dists/$zip_name.XXXXXX")
  tmp_dir=$(mktemp -d "$dists/unzip.XXXXXX")
  trap 'rm -rf "$tmp_zip" "$tmp_dir"; rmdir "$dists" 2>/dev/null || true' EXIT
  trap 'exit 130' INT TERM HUP
  echo "Downloading $url" >&2
  if command -v curl >/dev/null 2>&1; then curl -fsSL --retry 3 -o "$tmp_zip" "$url" || die "download of $url failed"
  elif command -v wget >/dev/null 2>&1; then wget -q -O "$tmp_zip" "$url" || die "download of $url failed"
  else die "curl or wget is needed to download $url"; fi
  actual=$(sha256 "$tmp_zip")
  [ "$actual" = "$sum" ] || die "$zip_name has SHA-256 $actual, not distributionSha256Sum $sum; refused"
  unzip -q "$tmp_zip" -d "$tmp_dir" || die "$zip_name could not be unpacked"
  top=$(ls "$tmp_dir")
  [ "$(printf '%s\n' "$top" | wc -l)" -eq 1 ] && [ -f "$tmp_dir/$top/bin/gradle" ] || die "$zip_name holds no single gradle-*/bin/gradle"
  printf '%s\n' "$top" > "$tmp_dir/.complete"
  if [ ! -f "$marker" ]; then # else another gradlew finished first
    rm -rf "$home"
    mv "$tmp_dir" "$home"
  fi
  rm -f "$tmp_zip"
  trap - EXIT INT TERM HUP
}

[ -f "$marker" ] || { rm -rf "$home"; install; }
gradle="$home/$(cat "$marker")/bin/gradle"
[ -f "$gradle" ] || die "$gradle missing; remove $home and run again"
exec sh "$gradle" "$@"
