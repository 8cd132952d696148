#!/usr/bin/env python3
"""Where a table's one-step-per-row dissipation departs from its sub-stepped limit, by node.

Usage: row_work_attribution.py FRETBEM CASE [--rows N] [--split S] [--base-split B]

CASE as in step_control_cost.py (sphere, displacement, rough): the table sampled at N rows a
period is run as it is (one step a row, load.substeps = 1) and with every row split in S equal
rows (the same piecewise-linear path), both saving the dissipation, state and pressure fields at every
step. Over the third period, each row's nodal work of the one-step run minus the reference's
over the same row ends is summed by the node's class in the one-step run: slipping at both
row ends (the trapezoid of the bound), starting to slip in the row (its end bound), losing
contact in it, and the rest (stuck or open at the row's end). Prints CSV per row and the sums
(J); the third period's error against the reference is their total. With --base-split B the
run scored is the path split in B rows a row (one step each) instead of the N rows, and S a
multiple of B.
"""
import argparse
import importlib.util
import os
import subprocess
import tempfile

import h5py

HERE = os.path.dirname(os.path.abspath(__file__))
spec = importlib.util.spec_from_file_location("cost", os.path.join(HERE, "step_control_cost.py"))
cost = importlib.util.module_from_spec(spec)
spec.loader.exec_module(cost)
SLIP = 2


def run_fields(binary, work, case, rows, split, names, tolerance=0.0):
    """Runs the N-row path of CASE split in `split` rows a row, saving the fields `names` at
    every step; returns its output directory."""
    tag = "%s_%d_%d" % (case, rows, split)
    table, ini, out = (os.path.join(work, tag + e) for e in (".csv", ".ini", "_out"))
    cost.write_table(table, case, rows, split)
    cost.write_scenario(ini, case, table, tolerance)
    subprocess.run([binary, "run", ini, "--out", out, "--quiet",
                    "--set", "output.fields=" + ",".join(names),
                    "--set", "output.fields_every=1"],
                   check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return out


def fields_by_time(out, names):
    """{time: {name: field}} of a run's saved fields, the last step saved at each time."""
    fields = {}
    with h5py.File(os.path.join(out, "result.h5"), "r") as f:
        for g in f["fields"].values():
            t, step = round(float(g.attrs["time"]), 10), int(g.attrs["step"])
            if t not in fields or fields[t][0] < step:
                fields[t] = (step, {k: g[k][()] for k in names})
    return {t: v[1] for t, v in fields.items()}


def run_with_fields(binary, work, case, rows, split):
    names = ("dissipation", "state", "pressure")
    return fields_by_time(run_fields(binary, work, case, rows, split, names), names)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("fretbem")
    ap.add_argument("case", choices=sorted(cost.CASES))
    ap.add_argument("--rows", type=int, default=32)
    ap.add_argument("--split", type=int, default=8)
    ap.add_argument("--base-split", type=int, default=1)
    a = ap.parse_args()
    c = cost.CASES[a.case]
    h2 = (c["length"] / c["n"]) ** 2
    with tempfile.TemporaryDirectory() as work:
        one = run_with_fields(a.fretbem, work, a.case, a.rows, a.base_split)
        ref = run_with_fields(a.fretbem, work, a.case, a.rows, a.split)
    ends = sorted(t for t in one if 2.0 <= t <= 3.0)
    classes = ("slip_both", "start_slip", "lose_contact", "rest")
    total = dict.fromkeys(classes, 0.0)
    print("time," + ",".join(classes))
    for t0, t1 in zip(ends, ends[1:]):
        d = ((one[t1]["dissipation"] - one[t0]["dissipation"]) -
             (ref[t1]["dissipation"] - ref[t0]["dissipation"])) * h2
        s0, s1 = one[t0]["state"] == SLIP, one[t1]["state"] == SLIP
        lose = (one[t0]["pressure"] > 0) & (one[t1]["pressure"] == 0)
        masks = (s0 & s1, ~s0 & s1, lose, ~s1 & ~lose)
        row = [float(d[m].sum()) for m in masks]
        for k, v in zip(classes, row):
            total[k] += v
        print("%.6f," % t1 + ",".join("%.3e" % v for v in row))
    print("sum," + ",".join("%.3e" % total[k] for k in classes))
    print("# third period: %d rows a row minus %d rows a row: %.4e J"
          % (a.base_split, a.split, sum(total.values())))


if __name__ == "__main__":
    main()
