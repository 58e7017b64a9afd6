#!/usr/bin/env bash
# Builds the paper's baselines (issue 21) from source checkouts: OpenMVG 2.1
# (structure from motion) and OpenMVS 2.3 (densify, mesh, refine) with the
# header-only VCG library. Neither is packaged in Debian 12; everything they
# need beyond their own sources comes from Debian (installed here with apt:
# cereal, CoinUtils, Clp and Osi for OpenMVG; Boost, OpenCV, CGAL, Eigen,
# Ceres for both). Nothing is downloaded: OpenMVG's git submodules (glfw,
# osi_clp, cereal) are replaced by the Debian packages, OpenMVS builds
# without CUDA and Python.
#
# Usage: bash scripts/baselines/build.sh --openmvg_src DIR --openmvs_src DIR
#          --vcg_src DIR [--prefix DIR] [--jobs N] [--only openmvg|openmvs]
#   *_src   git checkouts (a clone or a bare mirror) of openMVG/openMVG,
#           cdcseacave/openMVS and cnr-isti-vclab/vcglib; the pinned tags
#           below are exported from them, so the result does not depend on
#           what the checkouts have checked out
#   prefix  install and build root (default bench_work/baselines in the
#           checkout); binaries end in PREFIX/openmvg/bin and
#           PREFIX/openmvs/bin/OpenMVS
#   jobs    parallel compile jobs (default: the number of cores)
# About 35 min (OpenMVG) and 15 min (OpenMVS) on 2 cores; a re-run skips a
# library whose install already holds its binaries. Progress: cmake's own
# lines, and one line per minute with the build's elapsed time.
set -euo pipefail
cd "$(dirname "$0")/../.."
ROOT=$(pwd)

OPENMVG_TAG=v2.1
OPENMVS_TAG=v2.3.0
VCG_TAG=2023.12

OPENMVG_SRC=""
OPENMVS_SRC=""
VCG_SRC=""
PREFIX="${ROOT}/bench_work/baselines"
JOBS=$(nproc)
ONLY=""
while [[ $# -gt 0 ]]; do
  case "$1" in
    --openmvg_src) OPENMVG_SRC=$2; shift 2 ;;
    --openmvs_src) OPENMVS_SRC=$2; shift 2 ;;
    --vcg_src) VCG_SRC=$2; shift 2 ;;
    --prefix) PREFIX=$2; shift 2 ;;
    --jobs) JOBS=$2; shift 2 ;;
    --only) ONLY=$2; shift 2 ;;
    -h|--help) sed -n 2,23p "$0"; exit 0 ;;
    *) echo "build.sh: unknown argument $1" >&2; exit 2 ;;
  esac
done
log() { echo "[baselines/build $(date +%H:%M:%S)] $*"; }
fail() { echo "baselines/build: $*" >&2; exit 1; }
[[ "${ONLY}" == "" || "${ONLY}" == openmvg || "${ONLY}" == openmvs ]] ||
  fail "--only must be openmvg or openmvs, not '${ONLY}'"
[[ "${JOBS}" =~ ^[1-9][0-9]*$ ]] || fail "--jobs must be a positive integer, not '${JOBS}'"
want() { [[ -z "${ONLY}" || "${ONLY}" == "$1" ]]; }
if want openmvg; then
  [[ -n "${OPENMVG_SRC}" ]] || fail "--openmvg_src is required (a git checkout of openMVG/openMVG)"
fi
if want openmvs; then
  [[ -n "${OPENMVS_SRC}" ]] || fail "--openmvs_src is required (a git checkout of cdcseacave/openMVS)"
  [[ -n "${VCG_SRC}" ]] || fail "--vcg_src is required (a git checkout of cnr-isti-vclab/vcglib)"
fi

# The Debian packages of both builds (idempotent).
packages=(build-essential cmake git libeigen3-dev libceres-dev
  libcereal-dev coinor-libclp-dev coinor-libosi-dev coinor-libcoinutils-dev
  libjpeg-dev libpng-dev libtiff-dev
  libboost-iostreams-dev libboost-program-options-dev libboost-system-dev
  libboost-serialization-dev libopencv-dev libcgal-dev)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" ||
    missing+=("$p")
done
if [[ ${#missing[@]} -gt 0 ]]; then
  log "installing ${missing[*]}"
  SUDO=""
  [[ $(id -u) -eq 0 ]] || SUDO=sudo
  ${SUDO} apt-get install -y --no-install-recommends "${missing[@]}"
fi

# export_tag SRC TAG DEST: the tagged tree of a git checkout into DEST.
export_tag() {
  local src=$1 tag=$2 dest=$3
  git -C "${src}" rev-parse --verify -q "${tag}^{commit}" > /dev/null ||
    fail "${src} has no tag ${tag} (fetch the tags of its repository)"
  rm -rf "${dest}"
  mkdir -p "${dest}"
  # Not `git archive`: a mirror may lack the blobs of large sample files,
  # which the build does not need; they are skipped and listed.
  python3 "${ROOT}/scripts/baselines/export_git_tree.py" "${src}" "${tag}" "${dest}"
  log "exported ${tag} ($(git -C "${src}" rev-parse --short "${tag}^{commit}")) of ${src}"
}

source "${ROOT}/scripts/progress_lib.sh"
# with_progress LABEL CMD...: runs CMD, its output in LABEL's log, with a
# progress line a minute; fails naming the log.
with_progress() {
  local label=$1; shift
  local log_file="${PREFIX}/${label}.log"
  local start=${SECONDS}
  : > "${log_file}"
  run_with_progress "${label}" "${log_file}" "$@" ||
    { tail -n 30 "${log_file}" >&2; fail "${label} failed, see ${log_file}"; }
  log "${label}: done in $(( SECONDS - start )) s"
}

mkdir -p "${PREFIX}"

if want openmvg; then
  if [[ -x "${PREFIX}/openmvg/bin/openMVG_main_SfM" ]]; then
    log "OpenMVG already installed in ${PREFIX}/openmvg"
  else
    export_tag "${OPENMVG_SRC}" "${OPENMVG_TAG}" "${PREFIX}/src/openMVG"
    # OpenMVG's CMakeLists stops when its cereal submodule is not checked
    # out, even when Debian's cereal (found first) is the one used.
    mkdir -p "${PREFIX}/src/openMVG/src/dependencies/cereal/include"
    with_progress openmvg_configure cmake -S "${PREFIX}/src/openMVG/src" \
      -B "${PREFIX}/build/openMVG" -DCMAKE_BUILD_TYPE=Release \
      -DCMAKE_INSTALL_PREFIX="${PREFIX}/openmvg" \
      -DOpenMVG_BUILD_SHARED=OFF -DOpenMVG_BUILD_TESTS=OFF \
      -DOpenMVG_BUILD_DOC=OFF -DOpenMVG_BUILD_EXAMPLES=OFF \
      -DOpenMVG_BUILD_GUI_SOFTWARES=OFF -DOpenMVG_BUILD_OPENGL_EXAMPLES=OFF \
      -DOpenMVG_USE_OPENCV=OFF -DOpenMVG_USE_OPENMP=ON \
      -DCOINUTILS_INCLUDE_DIR_HINTS=/usr/include/coin \
      -DCLP_INCLUDE_DIR_HINTS=/usr/include/coin \
      -DOSI_INCLUDE_DIR_HINTS=/usr/include/coin
    with_progress openmvg_build cmake --build "${PREFIX}/build/openMVG" -j "${JOBS}"
    with_progress openmvg_install cmake --install "${PREFIX}/build/openMVG"
  fi
fi

if want openmvs; then
  if [[ -x "${PREFIX}/openmvs/bin/OpenMVS/DensifyPointCloud" ]]; then
    log "OpenMVS already installed in ${PREFIX}/openmvs"
  else
    export_tag "${VCG_SRC}" "${VCG_TAG}" "${PREFIX}/src/vcglib"
    export_tag "${OPENMVS_SRC}" "${OPENMVS_TAG}" "${PREFIX}/src/openMVS"
    with_progress openmvs_configure cmake -S "${PREFIX}/src/openMVS" \
      -B "${PREFIX}/build/openMVS" -DCMAKE_BUILD_TYPE=Release \
      -DCMAKE_INSTALL_PREFIX="${PREFIX}/openmvs" \
      -DVCG_ROOT="${PREFIX}/src/vcglib" \
      -DOpenMVS_USE_CUDA=OFF -DOpenMVS_USE_PYTHON=OFF \
      -DOpenMVS_USE_BREAKPAD=OFF -DOpenMVS_BUILD_TOOLS=ON
    with_progress openmvs_build cmake --build "${PREFIX}/build/openMVS" -j "${JOBS}"
    with_progress openmvs_install cmake --install "${PREFIX}/build/openMVS"
  fi
fi
log "binaries: ${PREFIX}/openmvg/bin, ${PREFIX}/openmvs/bin/OpenMVS"
