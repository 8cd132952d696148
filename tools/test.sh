#!/usr/bin/env bash
# Install what is missing, build every target, run the test suite. Extra arguments go to ctest
# (e.g. tools/test.sh -R half_space); the exit status is ctest's.
set -euo pipefail
# shellcheck source=tools/common.sh
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
cd "$FRETBEM_ROOT"

# The plotting packages are installed too: the suite tests the plot tools with them; and
# OpenMPI, so that the MPI sweep tests run (docs/cluster.md).
fretbem_install_dependencies --with-optional --with-mpi
# shellcheck disable=SC2119
fretbem_build

fretbem_log "running ctest"
exec ctest --test-dir "$FRETBEM_BUILD_DIR" --output-on-failure -j2 "$@"
