#!/usr/bin/env bash
# Installs what plslam needs from Debian packages (only what is missing), then configures
# and builds incrementally. Called by tools/map.sh and tools/test.sh; safe to run again:
# when everything is installed and built it takes a second or two.
#
#   PLSLAM_BUILD_DIR   build folder (default: build)
#   PLSLAM_BUILD_TYPE  CMake build type (default: Release)
#   PLSLAM_ROS=0       leave out the ROS 1 packages (bag input, the plslam_ros node and their
#                      tests are then not built; everything else is)
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build_dir="${PLSLAM_BUILD_DIR:-$root/build}"
build_type="${PLSLAM_BUILD_TYPE:-Release}"

packages=(
  build-essential cmake ninja-build ccache pkg-config
  libeigen3-dev libopencv-dev libopencv-contrib-dev libvisp-dev libceres-dev
  libpcl-dev liboctomap-dev libapriltag-dev libgtest-dev libgmock-dev libbenchmark-dev
  libpugixml-dev nlohmann-json3-dev libyaml-cpp-dev zlib1g-dev  # XML, JSON, YAML, CRC-32
  clang libclang-rt-14-dev  # libFuzzer and clang's sanitizer runtimes (fuzz/, CMakePresets.json `fuzz`)
)
# ROS 1 (Debian's Noetic-era packages): bag input, the plslam_ros node, rosmaster for its tests,
# roslaunch for tools/ros/*.launch, rosservice/rostopic/rosnode to talk to the node.
# 114 packages, 45 MB installed (docs/RESULTS.md).
if [ "${PLSLAM_ROS:-1}" != 0 ]; then
  packages+=(
    libroscpp-dev librosbag-dev libtf2-ros-dev libmessage-filters-dev
    libsensor-msgs-dev libnav-msgs-dev libgeometry-msgs-dev libvisualization-msgs-dev
    libdiagnostic-msgs-dev libstd-srvs-dev python3-rosmaster python3-roslaunch
    python3-rosservice python3-rostopic python3-rosnode python3-std-srvs
  )
fi

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done
if ((${#missing[@]})); then
  echo "plslam setup: installing ${#missing[@]} missing Debian packages: ${missing[*]}" >&2
  sudo=""
  if [ "$(id -u)" != 0 ]; then
    command -v sudo >/dev/null || { echo "plslam setup: not root and no sudo: install these packages first: ${missing[*]}" >&2; exit 1; }
    sudo=sudo
  fi
  export DEBIAN_FRONTEND=noninteractive
  $sudo apt-get update -qq
  $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

# Paths relative to the checkout in ccache's keys: a second clone reuses the first one's objects.
export CCACHE_BASEDIR="${CCACHE_BASEDIR:-$root}"
if [ ! -f "$build_dir/build.ninja" ]; then
  cmake -S "$root" -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE="$build_type" >/dev/null
fi
# Two jobs per core would swap on PCL-heavy files; one per core is the safe default.
ninja -C "$build_dir" -j "$(nproc)"
