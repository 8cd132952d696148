#!/usr/bin/env bash
# Quick start on a fresh Debian 12 machine: install what is missing, build build/fretbem, run a
# fretting loop (scenarios/mindlin_cycle.ini: Hertz sphere, tangential force +-0.6 mu F_z, 3
# cycles; n = 64 here for speed, a few seconds), and compare the energy dissipated per cycle
# with the Mindlin–Deresiewicz closed form (Johnson, Contact Mechanics, §7.5, eq. 7.59).
set -euo pipefail
# shellcheck source=tools/common.sh
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
cd "$FRETBEM_ROOT"

fretbem_install_dependencies --with-optional
fretbem_build fretbem

scenario=scenarios/mindlin_cycle.ini
n=64
out=out/quickstart
fretbem_log "running: $FRETBEM_BUILD_DIR/fretbem run $scenario --set grid.n=$n --out $out --overwrite"
"$FRETBEM_BUILD_DIR/fretbem" run "$scenario" --set grid.n=$n --out "$out" --overwrite

# Mindlin–Deresiewicz energy per full cycle between +-Q* at constant P (Johnson eq. 7.59), for
# a rigid sphere on an elastic half-space (the scenario has no second body):
#   W = 9 mu^2 P^2 / (10 a) (2 - nu)/G [1 - (1 - x)^(5/3) - (5x/6)(1 + (1 - x)^(2/3))],
#   x = Q*/(mu P), a = (3 P R / (4 E*))^(1/3), E* = E/(1 - nu^2), G = E/(2(1 + nu)).
# The inputs are read from the scenario file, not from the run.
mindlin_energy() {
  awk -F'=' '
    function val(s) { gsub(/[ \t]/, "", s); return s + 0 }
    /^[ \t]*E[ \t]*=/ { E = val($2) }  /^[ \t]*nu[ \t]*=/ { nu = val($2) }
    /^[ \t]*mu[ \t]*=/ { mu = val($2) } /^[ \t]*radius[ \t]*=/ { R = val($2) }
    /^[ \t]*normal_force[ \t]*=/ { P = val($2) } /^[ \t]*amplitude[ \t]*=/ { x = val($2) }
    END {
      Es = E / (1 - nu * nu); G = E / (2 * (1 + nu)); a = (3 * P * R / (4 * Es)) ^ (1 / 3)
      b = 1 - (1 - x) ^ (5 / 3) - 5 * x / 6 * (1 + (1 - x) ^ (2 / 3))
      printf "%.4e", 9 * mu * mu * P * P / (10 * a) * (2 - nu) / G * b
    }' "$1"
}

# The last cycle of cycles.csv (the first one starts from zero load, not on the loop).
last_cycle=$(tail -n 1 "$out/cycles.csv")
cycle=$(cut -d, -f1 <<<"$last_cycle")
energy=$(cut -d, -f3 <<<"$last_cycle")
closed=$(mindlin_energy "$scenario")
ratio=$(awk -v e="$energy" -v c="$closed" 'BEGIN { printf "%+.2f", 100 * (e / c - 1) }')

plot="(python3-matplotlib not installed: no plot; tools/plot_hysteresis.py $out draws it)"
if /usr/bin/python3 -c "import matplotlib" 2>/dev/null; then
  plot=$(/usr/bin/python3 tools/plot_hysteresis.py "$out" --out "$out/hysteresis.png" | grep "\.png$" | tail -n 1)
fi

cat <<MSG

fretbem is built: $FRETBEM_BUILD_DIR/fretbem (try --help).
Fretting loop $scenario at n = $n, results in $out/:
  energy dissipated in cycle $cycle:  $(printf '%.4e' "$energy") J
  Mindlin–Deresiewicz (Johnson §7.5): $closed J   (difference $ratio %)
  hysteresis plot:   $plot
  $out/timeseries.csv   one row per load step (README "Outputs")
  $out/cycles.csv       energy, loop area, amplitudes per cycle
  $out/result.h5        scenario, surfaces, fields, with units and coordinates (h5py, xarray)
  $out/result.xmf       the fields over time for ParaView: paraview $out/result.xmf
Run the tests with tools/test.sh.
MSG
