#!/usr/bin/env bash
# Install what is missing, build every target, run the test suite. Extra arguments go to ctest
# (e.g. tools/test.sh -R half_space); the exit status is ctest's.
# FRETBEM_WITH_PARAVIEW=1 also installs Debian's ParaView and Xvfb (~950 MB, ~8 min measured),
# so that the test paraview_xmf runs instead of being skipped.
#
#   tools/test.sh --sanitize [CTEST ARGS]   the same in build-sanitize/ with AddressSanitizer
#       and UndefinedBehaviorSanitizer (clang-14 when installed, which also traps overflowing
#       float-to-int casts; else the default compiler), the `unit` label: the unit tests and
#       the bad-input corpus (tests/bad_inputs). Any sanitizer report fails the test.
set -euo pipefail
# shellcheck source=tools/common.sh
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
cd "$FRETBEM_ROOT"

sanitize=0
if [[ "${1:-}" == --sanitize ]]; then
  sanitize=1
  shift
fi

# The plotting packages are installed too: the suite tests the plot tools with them (and the
# optional list carries clang-14 for the sanitized build); and OpenMPI, so that the MPI sweep
# tests run (docs/cluster.md).
paraview=()
[[ "${FRETBEM_WITH_PARAVIEW:-0}" == 1 ]] && paraview=(--with-paraview)
fretbem_install_dependencies --with-optional --with-mpi "${paraview[@]}"

if [[ $sanitize == 1 ]]; then
  FRETBEM_BUILD_DIR=build-sanitize
  fretbem_configure_sanitized
  # shellcheck disable=SC2119
  fretbem_build
  # halt_on_error: the first report fails the test; leaks are reported too (detect_leaks).
  export ASAN_OPTIONS=halt_on_error=1:detect_leaks=1:abort_on_error=0
  export UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1
  fretbem_log "running ctest -L unit (sanitized)"
  exec ctest --test-dir "$FRETBEM_BUILD_DIR" --output-on-failure -j2 -L unit "$@"
fi

# shellcheck disable=SC2119
fretbem_build

# The build above has MPI; the other side of the MPI-dependent files must compile too. A
# second full build without MPI would double CI's time for a few #ifdefs: check those files
# alone (a few seconds; without MPI installed it repeats what the build did).
for f in src/study/mpi_queue.cpp src/parallel/communicator.cpp src/elastic/mpi_engine.cpp \
  src/wear/grid_vector.cpp; do
  fretbem_log "checking $f without MPI (-fsyntax-only)"
  "${CXX:-c++}" -std=c++20 -fsyntax-only -Wall -Wextra -Werror -Iinclude -I/usr/include/eigen3 "$f"
done

fretbem_log "running ctest"
if [[ $# -gt 0 ]]; then  # a chosen subset: that alone
  exec ctest --test-dir "$FRETBEM_BUILD_DIR" --output-on-failure -j2 "$@"
fi
ctest --test-dir "$FRETBEM_BUILD_DIR" --output-on-failure -j2

# The whole suite passed. A quick sanitized subset follows: the bad-input corpus and the
# damaged-checkpoint and damaged-output tests under ASan + UBSan, the inputs most likely to
# reach memory errors. Measured: about 3.5 min to build fretbem and test_faults sanitized on 2
# cores, 1.5 min to run. FRETBEM_SKIP_SANITIZE=1 skips it; `tools/test.sh --sanitize` runs
# every unit test sanitized.
if [[ "${FRETBEM_SKIP_SANITIZE:-0}" == 1 ]]; then exit 0; fi
FRETBEM_BUILD_DIR=build-sanitize
fretbem_configure_sanitized
fretbem_build fretbem test_faults
export ASAN_OPTIONS=halt_on_error=1:detect_leaks=1:abort_on_error=0
export UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1
fretbem_log "running the sanitized quick subset (build-sanitize/)"
exec ctest --test-dir "$FRETBEM_BUILD_DIR" --output-on-failure -j2 \
  -R '^(bad_inputs|Faults\.(CorruptedCheckpointsAreRefused|DamagedOrForeignOutputsAreRefused|EditedInputFilesAreRefusedOnResume|CheckpointWithOldFormatNameResumes))$'
