#!/bin/bash
# Steady-cycle dissipation under a varying normal load against the step (docs/algorithms.md,
# "A moving bound within a step"): the sphere of mindlin_cycle.ini at n = 96 under
# F_z = P (1 + 0.3 sin 2 pi t), F_x = 0.5 mu P cos 2 pi t (P = 10 N, mu = 0.5), a table from
# t = -1/4 (F_x = 0) over three periods; prints, per steps-per-period count, the third
# period's dissipated_energy and loop_area (cycles.csv, cycle 2) and the CPU seconds. One
# solve a row (load.substeps = 1; `-- --set load.substeps=K` for K sub-steps a row).
# Usage: tools/bench/varying_normal_convergence.sh FRETBEM ROWS_PER_PERIOD... [-- --set k=v ...]
set -euo pipefail
bin=$1; shift
rows=(); while [ $# -gt 0 ] && [ "$1" != "--" ]; do rows+=("$1"); shift; done
[ $# -gt 0 ] && shift
work=$(mktemp -d); trap 'rm -rf "$work"' EXIT
echo "rows_per_period,dissipated_energy,loop_area,cpu_s"
for N in "${rows[@]}"; do
  /usr/bin/python3 - "$N" > "$work/t$N.csv" <<'PY'
import math, sys
N, P, mu = int(sys.argv[1]), 10.0, 0.5
print("time,Fz,Fx")
for j in range(3 * N + N // 4 + 1):
    t = -0.25 + j / N
    print("%.17g,%.17g,%.17g" % (t, P * (1 + 0.3 * math.sin(2 * math.pi * t)),
                                 0.5 * mu * P * math.cos(2 * math.pi * t)))
PY
  cat > "$work/s$N.ini" <<INI
[material]
E = 210e9
nu = 0.3
mu = 0.5
[grid]
n = 96
length = 2.8e-4
[surface]
type = sphere
radius = 0.01
[load]
path = table
table = t$N.csv
substeps = 1
[solver]
stiffness = none
INI
  cpu=$( { /usr/bin/time -f "%U %S" "$bin" run "$work/s$N.ini" --out "$work/o$N" --quiet "$@" \
           >/dev/null 2>"$work/err$N"; } 2>&1; tail -1 "$work/err$N" | awk '{print $1 + $2}')
  echo "$N,$(grep '^2,' "$work/o$N/cycles.csv" | cut -d, -f3,4),$cpu"
done
