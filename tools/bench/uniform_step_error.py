#!/usr/bin/env python3
"""The step_error of uniform steps against their measured error (docs/algorithms.md,
"Error-controlled load steps"): step_control_cost.py's 32-row path of CASE split in s rows a row,
run with load.tolerance = 1e-2, which subdivides none of its rows, so the run is the fixed split
with the cycle's step_error (after the division by 3) beside it.

Usage: uniform_step_error.py FRETBEM CASE LIMIT [--splits 1,2,4]
LIMIT: the path's step limit in J (the header of `step_control_cost.py FRETBEM CASE`).
Prints CSV: rows a period, error of the third period's dissipation, step_error, their ratio.
"""
import argparse
import os
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import step_control_cost as bench  # noqa: E402


def arguments():
    """FRETBEM CASE LIMIT [--splits 1,2,4], as the usage above (estimate_fidelity.py's too)."""
    ap = argparse.ArgumentParser()
    ap.add_argument("fretbem")
    ap.add_argument("case", choices=sorted(bench.CASES))
    ap.add_argument("limit", type=float)
    ap.add_argument("--splits", default="1,2,4")
    return ap.parse_args()


def main():
    a = arguments()
    print("rows_per_period,error,step_error,ratio")
    with tempfile.TemporaryDirectory() as work:
        for split in (int(s) for s in a.splits.split(",")):
            d, _, _, est, _, _ = bench.run(a.fretbem, work, a.case, 32, split, 1e-2)
            err = d / a.limit - 1
            print("%d,%+.3e,%.3e,%.2f" % (32 * split, err, est, est / abs(err)))
            sys.stdout.flush()


if __name__ == "__main__":
    main()
