# shellcheck shell=bash
# Shared set-up for tools/quickstart.sh and tools/test.sh: install what is missing, then
# configure and build. Sourced, not executed; callers have `set -euo pipefail`.
#
# Environment:
#   FRETBEM_BUILD_DIR  build directory, relative to the repository root (default: build)
#   FRETBEM_JOBS       parallel build jobs (default: ninja's own choice)
#   FRETBEM_NO_INSTALL set to 1 to skip the package check (e.g. a machine you do not own)

# The repository root, from this file's location, so the scripts work from any directory.
FRETBEM_ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
FRETBEM_BUILD_DIR="${FRETBEM_BUILD_DIR:-build}"

# Everything the build and the tests need (CMakeLists.txt's find_package/pkg-config list).
FRETBEM_REQUIRED_PACKAGES=(
  build-essential cmake ninja-build pkg-config
  libeigen3-dev libfftw3-dev libsundials-dev libhdf5-dev libboost-program-options-dev
  libgtest-dev googletest python3
  pybind11-dev python3-dev python3-numpy
  libxdmf-dev libzip-dev libpugixml-dev
)
# MPI is optional for the build (FRETBEM_MPI=AUTO finds it); tools/test.sh installs it so that
# the suite also runs the MPI sweep tests (tests/test_sweep_mpi.cpp, ~10-20 s; docs/cluster.md)
# and the distributed-grid tests (tests/*_mpi.cpp with FFTW-MPI; docs/mpi-grid.md).
FRETBEM_MPI_PACKAGES=(libopenmpi-dev openmpi-bin libfftw3-mpi-dev)
# Only the plotting scripts (tools/plot_*.py), h5dump and the xarray test of result.h5
# (tests/python/test_result_xarray.py) use these; clang-14 and its runtime build the sanitized
# tests with float-cast-overflow and the libFuzzer targets (tools/test.sh --sanitize,
# docs/reliability.md).
FRETBEM_OPTIONAL_PACKAGES=(python3-numpy python3-h5py python3-matplotlib hdf5-tools
  python3-xarray python3-h5netcdf clang-14 libclang-rt-14-dev)
# Debian's ParaView and an X server for the test that reads result.xmf back with it
# (tests/python/paraview_xmf_test.py, skipped without them). Opt-in: measured 179 packages,
# 947 MB installed, ~8 min to fetch and unpack on a loaded 2-core machine.
FRETBEM_PARAVIEW_PACKAGES=(paraview xvfb)

fretbem_log() { printf '==> %s\n' "$*" >&2; }

# Prints the packages among "$@" that dpkg does not report as installed.
fretbem_missing_packages() {
  local pkg
  for pkg in "$@"; do
    if [[ "$(dpkg-query -W -f='${db:Status-Status}' "$pkg" 2>/dev/null || true)" != installed ]]; then
      printf '%s\n' "$pkg"
    fi
  done
}

# Runs a command as root: directly when we are root (CI containers have no sudo), else via sudo.
fretbem_as_root() {
  if [[ "$(id -u)" -eq 0 ]]; then
    "$@"
  elif command -v sudo >/dev/null 2>&1; then
    sudo "$@"
  else
    fretbem_log "need root to run: $*  (run as root or install sudo)"
    return 1
  fi
}

# Installs the missing packages of the given list; `apt-get update` only when something is
# missing, so a provisioned machine never touches the network.
# Usage: fretbem_install required|mpi|optional|paraview
fretbem_install() {
  local kind="$1" missing
  local -a wanted
  if [[ "$kind" == required ]]; then
    wanted=("${FRETBEM_REQUIRED_PACKAGES[@]}")
  elif [[ "$kind" == mpi ]]; then
    wanted=("${FRETBEM_MPI_PACKAGES[@]}")
  elif [[ "$kind" == paraview ]]; then
    wanted=("${FRETBEM_PARAVIEW_PACKAGES[@]}")
  else
    wanted=("${FRETBEM_OPTIONAL_PACKAGES[@]}")
  fi
  if ! command -v dpkg-query >/dev/null 2>&1; then
    fretbem_log "no dpkg-query: not a Debian system, assuming the $kind packages are present"
    return 0
  fi
  mapfile -t missing < <(fretbem_missing_packages "${wanted[@]}")
  if [[ ${#missing[@]} -eq 0 ]]; then
    fretbem_log "$kind packages present"
    return 0
  fi
  fretbem_log "installing $kind packages: ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  fretbem_as_root apt-get update
  fretbem_as_root apt-get install -y --no-install-recommends "${missing[@]}"
}

fretbem_install_dependencies() {
  if [[ "${FRETBEM_NO_INSTALL:-0}" == 1 ]]; then
    fretbem_log "FRETBEM_NO_INSTALL=1: skipping the package check"
    return 0
  fi
  fretbem_install required
  local flag
  for flag in "$@"; do
    case "$flag" in
      --with-mpi)
        # Without MPI the build still works (sweeps run in one process): do not stop here.
        fretbem_install mpi || fretbem_log "OpenMPI not installed; building without MPI sweeps"
        ;;
      --with-paraview)
        fretbem_install paraview || fretbem_log "ParaView not installed; paraview_xmf is skipped"
        ;;
      --with-optional)
        # Plotting extras are a convenience: a failure here must not stop the build.
        fretbem_install optional ||
          fretbem_log "optional plotting packages not installed; continuing"
        ;;
      *) fretbem_log "fretbem_install_dependencies: unknown option $flag" ;;
    esac
  done
}

# Configures $FRETBEM_BUILD_DIR on first use for ASan + UBSan (tools/test.sh --sanitize):
# clang-14 when installed (it also traps overflowing float-to-int casts), else the default.
fretbem_configure_sanitized() {
  local dir="$FRETBEM_ROOT/$FRETBEM_BUILD_DIR"
  [[ -f "$dir/CMakeCache.txt" ]] && return 0
  local -a compilers=()
  if command -v clang++-14 >/dev/null 2>&1; then
    compilers=(-DCMAKE_C_COMPILER=clang-14 -DCMAKE_CXX_COMPILER=clang++-14)
  fi
  fretbem_log "configuring $FRETBEM_BUILD_DIR/ (sanitized, Ninja)"
  cmake -S "$FRETBEM_ROOT" -B "$dir" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DFRETBEM_SANITIZE=ON -DFRETBEM_PYTHON=OFF "${compilers[@]}"
}

# Configures (Release, Ninja) on first use and builds the given targets (default: all).
fretbem_build() {
  local dir="$FRETBEM_ROOT/$FRETBEM_BUILD_DIR"
  local -a jobs=()
  [[ -n "${FRETBEM_JOBS:-}" ]] && jobs=(--parallel "$FRETBEM_JOBS")
  if [[ ! -f "$dir/CMakeCache.txt" ]]; then
    fretbem_log "configuring $FRETBEM_BUILD_DIR/ (Release, Ninja)"
    cmake -S "$FRETBEM_ROOT" -B "$dir" -G Ninja -DCMAKE_BUILD_TYPE=Release
  fi
  fretbem_log "building ${*:-all targets}"
  if [[ $# -gt 0 ]]; then
    cmake --build "$dir" "${jobs[@]}" --target "$@"
  else
    cmake --build "$dir" "${jobs[@]}"
  fi
}
