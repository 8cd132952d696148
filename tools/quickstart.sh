#!/usr/bin/env bash
# Quick start on a fresh Debian 12 machine: install what is missing, build build/fretbem, run
# the Hertz scenario (normal contact only) and say where its results are.
set -euo pipefail
# shellcheck source=tools/common.sh
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
cd "$FRETBEM_ROOT"

fretbem_install_dependencies --with-optional
fretbem_build fretbem

out=out/hertz
fretbem_log "running: $FRETBEM_BUILD_DIR/fretbem run scenarios/hertz.ini --out $out --overwrite"
"$FRETBEM_BUILD_DIR/fretbem" run scenarios/hertz.ini --out "$out" --overwrite

cat <<MSG

fretbem is built: $FRETBEM_BUILD_DIR/fretbem (try --help).
Results of scenarios/hertz.ini are in $out/:
  $out/timeseries.csv   one row per load step (DESIGN.md §4 columns)
  $out/result.h5        resolved scenario, surface and fields (h5dump -H $out/result.h5)
Run the tests with tools/test.sh.
MSG
