#!/usr/bin/env bash
# Install what is missing, build every target, run the test suite. Extra arguments go to ctest
# (e.g. tools/test.sh -R half_space); the exit status is ctest's.
set -euo pipefail
# shellcheck source=tools/common.sh
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
cd "$FRETBEM_ROOT"

# Required packages and OpenMPI (the MPI sweep tests run when it is there).
fretbem_install_dependencies --with-mpi
# shellcheck disable=SC2119
fretbem_build

fretbem_log "running ctest"
exec ctest --test-dir "$FRETBEM_BUILD_DIR" --output-on-failure -j2 "$@"
