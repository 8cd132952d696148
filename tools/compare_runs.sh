#!/usr/bin/env bash
# Runs every shipped scenario (or the ones named) with two fretbem binaries and compares their
# timeseries.csv and cycles.csv byte for byte; differing files are then compared per column as
# the largest |difference| over the column's largest |value|, so a change can be judged against
# the solver tolerance.
#
# usage: tools/compare_runs.sh OLD_BINARY NEW_BINARY [SCENARIO.ini ...]
# Outputs go to a temporary folder (kept when something differs). Exit 1 if anything differs.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
old="$(realpath "$1")" new="$(realpath "$2")"
shift 2
scenarios=("$@")
[[ ${#scenarios[@]} -eq 0 ]] && scenarios=("$root"/scenarios/*.ini)
work="$(mktemp -d "${TMPDIR:-/tmp}/fretbem_compare.XXXXXX")"
status=0
for s in "${scenarios[@]}"; do
  name="$(basename "$s" .ini)"
  for side in old new; do
    bin="$old"; [[ $side == new ]] && bin="$new"
    if ! "$bin" run "$s" --quiet --out "$work/$side/$name" > "$work/$side.$name.log" 2>&1; then
      echo "$name: the $side binary failed (see $work/$side.$name.log)"; status=1
    fi
  done
  for f in timeseries.csv cycles.csv; do
    a="$work/old/$name/$f" b="$work/new/$name/$f"
    [[ -f $a || -f $b ]] || continue
    if cmp -s "$a" "$b"; then
      echo "$name/$f: identical"
    else
      status=1
      /usr/bin/python3 - "$a" "$b" "$name/$f" <<'PY'
import sys, math
a, b, label = sys.argv[1:]
def read(p):
    rows = [l.rstrip("\n").split(",") for l in open(p) if l.strip()]
    return rows[0], rows[1:]
ha, ra = read(a); hb, rb = read(b)
if ha != hb or len(ra) != len(rb):
    print(f"{label}: DIFFERS in columns or row count ({len(ra)} vs {len(rb)} rows)"); sys.exit()
# |difference| relative to the column's largest |value|: a round-off zero (F_x at a turning
# point, 1e-16 against 1e2) must not read as a 100 % change.
top = {}
for x, y in zip(ra, rb):
    for name, u, v in zip(ha, x, y):
        for w in (float(u), float(v)):
            if not math.isnan(w): top[name] = max(top.get(name, 0.0), abs(w))
worst = {}
for x, y in zip(ra, rb):
    for name, u, v in zip(ha, x, y):
        u, v = float(u), float(v)
        if u == v or (math.isnan(u) and math.isnan(v)): continue
        d = abs(u - v) / max(top[name], 1e-300)
        worst[name] = max(worst.get(name, 0), d)
print(f"{label}: DIFFERS; largest |difference| / column's largest |value|: " +
      ", ".join(f"{k} {v:.2g}" for k, v in sorted(worst.items(), key=lambda kv: -kv[1])))
PY
    fi
  done
done
[[ $status -eq 0 ]] && rm -rf "$work" || echo "outputs kept in $work"
exit $status
