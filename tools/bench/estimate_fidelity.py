#!/usr/bin/env python3
"""Cheap per-step error estimates against the measured error of a cycle's dissipation
(docs/algorithms.md, "Run time against error": the estimate's fidelity).

Usage: estimate_fidelity.py FRETBEM CASE LIMIT [--splits 1,2,4]

step_control_cost.py's 32-row path of CASE split in s rows a row, run with load.tolerance = 1e-2
(which subdivides none of its rows: the fixed split, with step_error beside it), saving the
pressure, traction, state, slip and dissipation fields at every step. From the fields of three
neighbouring step ends (spans h0, h1; g = mu p the bound, s the slip length of a node slipping at
the step's end, tau the traction) each candidate is summed over the third period's steps, in J
relative to the period's dissipated energy, and divided by the measured |error| against LIMIT
(the path's step limit in J, the header of `step_control_cost.py FRETBEM CASE`):
  step_error      the program's (cycles.csv), the trapezoid's error |sum e| / 3 per step over
                  the step's dissipation scale;
  trapezoid       the same e = h1^2 (dg0 s1 - dg1 s0) / (6 h0 (h0 + h1)) summed with its sign,
                  / 3, in J of the period;
  within_row      |sum e| per step (undivided) of the steps whose step before lies on the same
                  row of the 32-row table (the path is C1 there), times s / (s - 1) for the
                  first step of each row, which has none (nan at s = 1);
  predictor       (a): the traction extrapolated linearly from the two step ends before,
                  sum |tau1 - tau_pred| s1 (J/m^2: the predictor's traction defect along the
                  step's slip);
  bound_dip       (b): nodes not slipping at the step's end whose traction at mid-step (the
                  mean of its ends) exceeds the bound at mid-step (quadratic through the three
                  ends): sum g1 c (|tau_mid| - g_mid), c = 4 a ln(1 + sqrt 2)(1 - nu^2)/(pi E),
                  Love's centre compliance of a uniform cell of side a (the slip it would take);
  curvature_Fz    the trapezoid's error from the bound's curvature within a row at a constant
                  slip rate: F_z is linear in time between the table's rows and g a smooth
                  function of F_z, so -(1/12) g_FF dF1^2 s1, g_FF the second divided
                  difference of g in F_z over the three ends.
Prints CSV: rows a period, the error, then each candidate's ratio estimate / |error|.
"""
import csv
import math
import os
import sys
import tempfile

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import row_work_attribution as attribution  # noqa: E402
import step_control_cost as bench  # noqa: E402
import uniform_step_error as uniform  # noqa: E402

FIELDS = ("pressure", "traction_x", "traction_y", "state", "slip_x", "slip_y", "dissipation")
SLIP = 2
E, NU = 210e9, 0.3  # step_control_cost.write_scenario's material


def run(binary, work, case, split):
    """The split run's step ends: [(time, F_z, fields)], and its third period's dissipation and
    step_error."""
    out = attribution.run_fields(binary, work, case, 32, split, FIELDS, tolerance=1e-2)
    ends = attribution.fields_by_time(out, FIELDS)
    with open(os.path.join(out, "timeseries.csv")) as f:
        fz = {round(float(r["time"]), 10): float(r["Fz"]) for r in csv.DictReader(f)}
    with open(os.path.join(out, "cycles.csv")) as f:
        third = {r["cycle"]: r for r in csv.DictReader(f)}["2"]
    steps = [(t, fz[t], ends[t]) for t in sorted(ends)]
    return steps, float(third["dissipated_energy"]), float(third["step_error"])


def step_candidates(a, b, c, area_cell, side):
    """The candidates (J/m^2 summed over the nodes) of step b -> c, a the step end before b."""
    (ta, fa, A), (tb, fb, B), (tc, fc, C) = a, b, c
    h0, h1 = tb - ta, tc - tb
    g = [bench.MU * X["pressure"] for X in (A, B, C)]
    slipping = [X["state"] == SLIP for X in (A, B, C)]
    s0 = np.where(slipping[1], np.hypot(B["slip_x"] - A["slip_x"], B["slip_y"] - A["slip_y"]), 0)
    s1 = np.where(slipping[2], np.hypot(C["slip_x"] - B["slip_x"], C["slip_y"] - B["slip_y"]), 0)
    e = h1 * h1 / (6 * h0 * (h0 + h1)) * ((g[1] - g[0]) * s1 - (g[2] - g[1]) * s0)
    tau = [np.stack([X["traction_x"], X["traction_y"]]) for X in (A, B, C)]
    pred = tau[1] + (h1 / h0) * (tau[1] - tau[0])
    defect = np.sqrt(((tau[2] - pred) ** 2).sum(0))
    curv = ((g[2] - g[1]) / h1 - (g[1] - g[0]) / h0) / (0.5 * (h0 + h1))
    g_mid = 0.5 * (g[1] + g[2]) - curv * h1 * h1 / 8
    tau_mid = np.sqrt(((0.5 * (tau[1] + tau[2])) ** 2).sum(0))
    excess = np.where(~slipping[2] & (g[2] > 0), np.maximum(0.0, tau_mid - g_mid), 0.0)
    compliance = 4 * side * math.log(1 + math.sqrt(2)) * (1 - NU * NU) / (math.pi * E)
    out = {"trapezoid": e.sum() / 3, "within_row": abs(e.sum()), "predictor": (defect * s1).sum(),
           "bound_dip": compliance * (g[2] * excess).sum(), "curvature_Fz": 0.0}
    if min(abs(fc - fb), abs(fb - fa), abs(fc - fa)) > 1e-9 * abs(fc):
        gff = 2 * ((g[2] - g[1]) / (fc - fb) - (g[1] - g[0]) / (fb - fa)) / (fc - fa)
        out["curvature_Fz"] = (-(1 / 12) * gff * (fc - fb) ** 2 * s1).sum()
    return {k: v * area_cell for k, v in out.items()}


def main():
    a = uniform.arguments()
    c = bench.CASES[a.case]
    side = c["length"] / c["n"]
    names = ("step_error", "trapezoid", "within_row", "predictor", "bound_dip", "curvature_Fz")
    print("rows_per_period,error," + ",".join(names))
    with tempfile.TemporaryDirectory() as work:
        for split in (int(s) for s in a.splits.split(",")):
            steps, d, step_error = run(a.fretbem, work, a.case, split)
            sums = dict.fromkeys(names[1:], 0.0)
            for i in range(2, len(steps)):
                if math.ceil(steps[i][0] - 1e-12) - 1 != 2:  # the third period's rows
                    continue
                for k, v in step_candidates(*steps[i - 2:i + 1], side * side, side).items():
                    if k == "within_row":  # step i is the first of its row when (i - 1) % s == 0
                        v = 0.0 if (i - 1) % split == 0 else v * split / (split - 1)
                    sums[k] += v / d
            if split == 1:  # no step has its step before on its own row
                sums["within_row"] = float("nan")
            err = d / a.limit - 1
            ratios = [step_error / abs(err)] + [sums[k] / abs(err) for k in names[1:]]
            print("%d,%+.3e," % (32 * split, err) + ",".join("%.2f" % r for r in ratios))
            sys.stdout.flush()


if __name__ == "__main__":
    main()
