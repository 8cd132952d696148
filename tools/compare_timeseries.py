#!/usr/bin/python3
"""Compare two runs' timeseries.csv column by column, relative to the solver tolerance.

usage: compare_timeseries.py A/timeseries.csv B/timeseries.csv [--tolerance 1e-8]

Per physical column: max |a - b| over the rows, divided by the column's largest |value| (its
scale), printed in units of the solver tolerance. Iteration and convolution counts are
reported as they are (they may differ when a change alters the solver's path), residual
columns as their largest values. Exit 1 when the
rows or columns differ, or a physical column differs by more than 100 tolerances (the
observables of a solve converged to relative residual tol are accurate to a few hundred tol
at most: sums over many nodes of errors of order tol).
"""
import csv
import math
import sys


def read(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    return rows[0], rows[1:]


def value(s):
    return float(s) if s not in ("", "nan") else math.nan


def main(argv):
    args = [a for a in argv[1:] if not a.startswith("--")]
    tol = 1e-8
    if "--tolerance" in argv:
        tol = float(argv[argv.index("--tolerance") + 1])
        args.remove(argv[argv.index("--tolerance") + 1])
    if len(args) != 2:
        sys.exit(__doc__)
    (ha, ra), (hb, rb) = read(args[0]), read(args[1])
    if ha != hb or len(ra) != len(rb):
        print(f"different shape: {len(ra)} vs {len(rb)} rows, columns equal: {ha == hb}")
        return 1
    counts = ("normal_iterations", "tangential_iterations", "convolutions", "step")
    worst = 0.0
    for j, name in enumerate(ha):
        a = [value(r[j]) for r in ra]
        b = [value(r[j]) for r in rb]
        if name.endswith("_residual"):  # the solves' own residuals: both must be <= tol
            print(f"{name:24s} largest: {max(a):.3g} vs {max(b):.3g}")
            continue
        if name in counts:
            diff = sum(x != y for x, y in zip(a, b))
            print(f"{name:24s} rows differing: {diff}")
            continue
        both = [(x, y) for x, y in zip(a, b) if not (math.isnan(x) or math.isnan(y))]
        nan_mismatch = sum(math.isnan(x) != math.isnan(y) for x, y in zip(a, b))
        scale = max([abs(x) for x, _ in both] + [0.0])
        d = max([abs(x - y) for x, y in both] + [0.0])
        rel = d / scale / tol if scale > 0 else 0.0
        worst = max(worst, rel)
        extra = f"  ({nan_mismatch} rows nan in one only)" if nan_mismatch else ""
        print(f"{name:24s} max |diff| / scale = {rel:9.3g} tol{extra}")
    print(f"worst physical column: {worst:.3g} x tolerance {tol:g}")
    return 0 if worst <= 100 else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv))
