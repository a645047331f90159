#!/usr/bin/env bash
# Installs the Debian packages the Android build needs when any is missing
# (everything else comes through Maven). Needs root or sudo for the install.
set -euo pipefail
missing=()
for tool in aapt2:aapt zipalign:zipalign apksigner:apksigner zip:zip unzip:unzip perl:perl-base java:openjdk-17-jdk-headless mvn:maven; do
  command -v "${tool%%:*}" >/dev/null 2>&1 || missing+=("${tool##*:}")
done
[ ${#missing[@]} -eq 0 ] && exit 0
echo "Installing ${missing[*]}" >&2
sudo=""
[ "$(id -u)" -eq 0 ] || sudo="sudo"
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq
$sudo apt-get install -y -qq "${missing[@]}" >/dev/null
