#!/usr/bin/env bash
# Sets up a fresh Debian bookworm machine for dloam, builds it (Release) and runs the main job:
# simulate a short dynamic urban drive, run the SLAM on it and evaluate it.
#   bash scripts/setup.sh            # as root (or with sudo available)
# Environment: DLOAM_BUILD_DIR (default build), DLOAM_SKIP_APT=1 to skip the package step,
#              DLOAM_SKIP_DEMO=1 to only build.
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD_DIR=${DLOAM_BUILD_DIR:-build}

PACKAGES=(cmake ninja-build g++ pkg-config
  libeigen3-dev libtbb-dev libnanoflann-dev libyaml-cpp-dev libcli11-dev nlohmann-json3-dev
  libtinyxml2-dev libspdlog-dev libfmt-dev libgtest-dev libgmock-dev libbenchmark-dev libembree-dev libceres-dev robin-map-dev gnuplot-nox libtorch-dev
  libpcap-dev libsqlite3-dev liblz4-dev libzstd-dev zlib1g-dev liblzma-dev nettle-dev liboctomap-dev
  pybind11-dev python3-dev python3-numpy python3-pytest chromium libpng-dev
  librosbag-storage-dev libsensor-msgs-dev libroscpp-dev libnav-msgs-dev libtf2-ros-dev
  clang libclang-rt-14-dev)

if [[ "${DLOAM_SKIP_APT:-0}" != 1 ]]; then
  missing=()
  for p in "${PACKAGES[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  if ((${#missing[@]})); then
    SUDO=""
    [[ $(id -u) -ne 0 ]] && SUDO=sudo
    echo "== installing ${#missing[@]} Debian packages: ${missing[*]}"
    $SUDO apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
  fi
fi

echo "== configuring and building ($BUILD_DIR, Release)"
cmake -S . -B "$BUILD_DIR" -G Ninja -DCMAKE_BUILD_TYPE=Release
cmake --build "$BUILD_DIR" -j"$(nproc)"

if [[ "${DLOAM_SKIP_DEMO:-0}" != 1 ]]; then
  echo "== main job: simulate a dynamic urban drive, run the SLAM, evaluate"
  bash scripts/demo.sh "$BUILD_DIR"
fi
