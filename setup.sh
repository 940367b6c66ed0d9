#!/usr/bin/env bash
# One entry point for a fresh Debian 12 machine:
#   ./setup.sh demo   install what is missing, build, generate the demo dataset, run pipelines/demo.toml
#   ./setup.sh test   install what is missing, build, run every test suite and
#                     the sanitizer job (fuzz/run.sh: the readers fuzzed under ASan/UBSan)
#   ./setup.sh build  install what is missing and build
set -euo pipefail
cd "$(dirname "$0")"

PACKAGES=(build-essential cmake ninja-build ccache git pkg-config
  libeigen3-dev libboost-dev libboost-filesystem-dev libboost-system-dev
  libtoml11-dev nlohmann-json3-dev libcli11-dev libgtest-dev libgmock-dev
  libpcl-dev liboctomap-dev libopenvdb-dev libembree-dev libflann-dev
  libceres-dev libtbb-dev libtorch-dev libstb-dev chromium unzip python3 clang
  librosbag-storage-dev librosbag-dev libsensor-msgs-dev libnav-msgs-dev libgeometry-msgs-dev
  libtf2-msgs-dev libsqlite3-dev libzstd-dev liblz4-dev)
BUILD_DIR=${LISTA_BUILD_DIR:-build}

install_missing() {
  local missing=()
  for p in "${PACKAGES[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  if ((${#missing[@]})); then
    echo "setup: installing ${missing[*]}" >&2
    local sudo=""; [ "$(id -u)" = 0 ] || sudo=sudo
    $sudo apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y --no-install-recommends "${missing[@]}"
  fi
}

build() {
  cmake -S . -B "$BUILD_DIR" -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
  cmake --build "$BUILD_DIR" -j "$(nproc)"
}

case "${1:-}" in
  build) install_missing; build ;;
  test)
    install_missing; build
    ctest --test-dir "$BUILD_DIR" --output-on-failure -j "$(nproc)"
    bash fuzz/run.sh "${BUILD_DIR}-fuzz" ;;
  demo)
    install_missing; build
    bash scripts/demo.sh "$BUILD_DIR" ;;
  *) echo "usage: ./setup.sh demo|test|build" >&2; exit 2 ;;
esac
