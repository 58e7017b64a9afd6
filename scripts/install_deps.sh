#!/usr/bin/env bash
# Installs every Debian 12 package that the build, the tests and a run need,
# including the stock colmap binary and clang-14 with libFuzzer for the fuzz
# targets (scripts/fuzz.sh). Idempotent and non-interactive.
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config git ca-certificates
  colmap sqlite3 python3 python3-numpy python3-matplotlib
  libeigen3-dev libceres-dev libgoogle-glog-dev libgflags-dev
  libopencv-dev libopencv-contrib-dev
  libpcl-dev libcgal-dev libflann-dev libembree-dev libtbb-dev
  libsqlite3-dev libyaml-cpp-dev nlohmann-json3-dev
  libopenmpi-dev openmpi-bin
  libboost-program-options-dev libboost-graph-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  clang-14 libclang-rt-14-dev
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install_deps: all ${#packages[@]} packages are installed"
  exit 0
fi

SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
echo "install_deps: installing ${missing[*]}"
$SUDO apt-get update -qq
DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
