#!/usr/bin/env bash
# Installs the Debian packages the Android build needs when any is missing
# (everything else comes through Maven; the export tests' Python readers through pip, below).
# Needs root or sudo for the Debian install.
set -euo pipefail
# The Python readers the export tests read their files back with (evo for EuRoC, PyYAML for
# Kalibr's imu.yaml, mcap with mcap-ros2-support and rosbags for ROS 2, OpenCV's FileStorage for the
# noise configurations of OpenVINS, VINS and ORB-SLAM3), from PyPI where pip
# reaches it; without them those tests are skipped, so a failed install only says so.
if command -v python3 >/dev/null 2>&1 && ! python3 -c "import evo, yaml, mcap_ros2.decoder, rosbags.highlevel, cv2" >/dev/null 2>&1; then
  timeout 300 python3 -m pip install -q --disable-pip-version-check evo pyyaml mcap mcap-ros2-support rosbags opencv-python-headless >/dev/null 2>&1 ||
    echo "note: pip could not install the export readers (evo, pyyaml, mcap, mcap-ros2-support, rosbags, opencv-python-headless): their tests will be skipped" >&2
fi
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
