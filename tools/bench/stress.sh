#!/bin/sh
# Long stress cases (docs/stability.md) that do not fit in CI: a very rough surface (H = 0.1) at n = 512
# under a force-controlled sine to +-0.9 mu F_z, with both tangential algorithms. Prints the
# time series' last rows and the peak memory; a failed solve exits non-zero with one line.
# Usage: tools/bench/stress.sh [BUILD_DIR] [N]
set -eu
build=${1:-build}
n=${2:-512}
out=$(mktemp -d)
cat > "$out/h01.ini" <<INI
[material]
E = 1
nu = 0.3
mu = 0.5
[grid]
n = $n
length = 1
[surface]
type = rough
hurst = 0.1
rms_slope = 0.1
method = fourier
seed = 7
[load]
normal_force = 0.0035
path = sine
amplitude = 0.9
cycles = 1
steps_per_cycle = 8
[solver]
tolerance = 1e-10
threads = 1
INI
for alg in projected partition; do
  echo "== H = 0.1, n = $n, $alg"
  /usr/bin/time -f "wall %e s, peak RSS %M kB" "$build/fretbem" run "$out/h01.ini" \
    --set solver.algorithm=$alg --out "$out/$alg" --overwrite --quiet
  cut -d, -f1,4,6,11,12,17,18 "$out/$alg/timeseries.csv"
done
rm -rf "$out"
