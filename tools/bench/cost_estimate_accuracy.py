#!/usr/bin/env python3
"""Accuracy of `fretbem check`'s cost estimate against real runs
(docs/reliability.md, "Accuracy of check's cost estimate").

For each case: `fretbem check` (its calibration) and then `fretbem run` on the same scenario
and overrides; prints predicted vs measured FFT convolutions (stepped runs: the sum of
timeseries.csv's `convolutions` column; wear runs: simulated cycles) and CPU seconds (the run's
user + system CPU from os.wait4, so a loaded machine does not inflate it). Also times the
calibration alone. Usage:

    nice -n 10 tools/bench/cost_estimate_accuracy.py BUILD_DIR [OUT_DIR] [--case NAME ...]
    nice -n 10 tools/bench/cost_estimate_accuracy.py BUILD_DIR --step-control [--case NAME ...]

--step-control: the five cases of step_control_cost.py (its 32-row tables over 3.25 periods)
under load.tolerance 1e-3, 5e-4 and 1e-4 instead of the shipped scenarios. In parentheses:
the convolutions at the ends of the rate range `check` prints under load.tolerance, and the
measured over them.

Results are in docs/reliability.md ("Accuracy of check's cost estimate").
"""
import csv
import os
import re
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

# name, scenario, overrides
CASES = [
    ("mindlin n=64", "mindlin_cycle.ini", ["grid.n=64"]),
    ("mindlin n=128", "mindlin_cycle.ini", []),
    ("cattaneo n=128", "cattaneo.ini", []),
    ("rough cycle n=64", "rough_fretting_cycle.ini", []),
    ("rough cycle n=128", "rough_fretting_cycle.ini", ["grid.n=128"]),
    ("rough monotone n=256", "rough_monotone.ini", []),
    ("fretting wear n=64", "fretting_wear.ini", ["grid.n=64"]),
    ("fretting wear n=128", "fretting_wear.ini", []),
    ("rough wear n=64", "rough_fretting_wear.ini", ["grid.n=64"]),
    ("rough wear n=128 N=1e5 rtol=1e-2", "rough_fretting_wear.ini",
     ["grid.n=128", "wear.cycles=1e5", "wear.rtol=1e-2"]),
    ("gross-slip wear n=64", "gross_slip_wear.ini", ["grid.n=64"]),
]


def cpu_run(cmd):
    """Runs cmd; returns (stdout+stderr, CPU seconds of the child)."""
    p = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    out = p.stdout.read()
    _, status, ru = os.wait4(p.pid, 0)
    if os.waitstatus_to_exitcode(status) != 0:
        raise RuntimeError(" ".join(cmd) + " failed:\n" + out)
    return out, ru.ru_utime + ru.ru_stime


def num(pattern, text):
    m = re.search(pattern, text)
    return float(m.group(1)) if m else float("nan")


def measure(exe, name, scenario, sets, out_dir):
    sc = scenario if os.path.isabs(scenario) else os.path.join(ROOT, "scenarios", scenario)
    args = sum((["--set", s] for s in sets), [])
    chk, chk_cpu = cpu_run([exe, "check", sc] + args)
    _, nocal_cpu = cpu_run([exe, "check", sc, "--no-estimate"] + args)
    run_dir = os.path.join(out_dir, re.sub(r"[^a-z0-9]+", "_", name.lower()))
    out, run_cpu = cpu_run([exe, "run", sc, "--out", run_dir, "--overwrite", "--quiet"] + args)
    row = {"case": name, "calibration_cpu": chk_cpu - nocal_cpu, "run_cpu": run_cpu}
    if "wear stability cap" in chk:
        m = re.search(r"expected simulated cycles: ([0-9.e+]+)(?: to ([0-9.e+]+))?", chk)
        row["pred_low"] = float(m.group(1))
        row["pred_high"] = float(m.group(2) or m.group(1))
        row["measured"] = num(r"with ([0-9.e+]+) simulated cycles", out)
        m = re.search(r"cost: about ([0-9.e+]+)(?: to ([0-9.e+]+))? s", chk)
        row["pred_cpu_low"] = float(m.group(1))
        row["pred_cpu_high"] = float(m.group(2) or m.group(1))
        # CPU per simulated cycle: the run's against the estimate's (kWarmCostFactor).
        row["cycle_ratio"] = run_cpu / row["measured"] / num(r"FFT convolutions, ([0-9.e+]+) s", chk)
    else:
        row["pred_low"] = row["pred_high"] = num(r"cost: about ([0-9.e+]+) FFT", chk)
        with open(os.path.join(run_dir, "timeseries.csv")) as f:
            row["measured"] = sum(float(r["convolutions"]) for r in csv.DictReader(f))
        row["pred_cpu_low"] = row["pred_cpu_high"] = num(r"FFT convolutions, ([0-9.e+]+) s", chk)
        # load.tolerance: the convolutions at the ends of the step control's rate range.
        m = re.search(r"load.tolerance: ([0-9.e+]+) to ([0-9.e+]+) FFT", chk)
        if m:
            row["rate_range"] = (float(m.group(1)), float(m.group(2)))
    return row


STEP_CONTROL_CASES = ["sphere", "rough", "displacement", "rough_displacement", "cerruti"]
STEP_CONTROL_TOLERANCES = [1e-3, 5e-4, 1e-4]


def step_control_cases(out_dir):
    """(name, scenario path, no overrides) of step_control_cost.py's tables under load.tolerance."""
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    import step_control_cost as scc
    cases = []
    for case in STEP_CONTROL_CASES:
        for tol in STEP_CONTROL_TOLERANCES:
            tag = "%s_tol_%g" % (case, tol)
            table, ini = (os.path.join(out_dir, tag + e) for e in (".csv", ".ini"))
            scc.write_table(table, case, 32, 1)
            scc.write_scenario(ini, case, table, tol)
            cases.append(("%s tolerance %g" % (case, tol), ini, []))
    return cases


def main():
    exe = os.path.join(os.path.abspath(sys.argv[1]), "fretbem")
    out_dir = sys.argv[2] if len(sys.argv) > 2 and not sys.argv[2].startswith("--") else None
    only = [sys.argv[i + 1] for i, a in enumerate(sys.argv) if a == "--case"]
    out_dir = out_dir or tempfile.mkdtemp(prefix="cost_estimate_")
    os.makedirs(out_dir, exist_ok=True)
    cases = step_control_cases(out_dir) if "--step-control" in sys.argv else CASES
    print("| case | predicted | measured | measured / predicted | predicted CPU s | "
          "run CPU s | measured / predicted | calibration CPU s | run / predicted CPU per cycle |")
    print("|---|---|---|---|---|---|---|---|---|")
    for name, scenario, sets in cases:
        if only and not any(o in name for o in only):
            continue
        r = measure(exe, name, scenario, sets, out_dir)
        rng = lambda lo, hi, f: (f % lo) if lo == hi else (f % lo) + "–" + (f % hi)
        lo, hi = r.get("rate_range", (0, 0))
        pred_range = f" ({rng(lo, hi, '%.4g')})" if hi else ""
        ratio_range = f" ({rng(r['measured'] / hi, r['measured'] / lo, '%.2f')})" if hi else ""
        print(f"| {r['case']} | {rng(r['pred_low'], r['pred_high'], '%.4g')}{pred_range} | "
              f"{r['measured']:.4g} | "
              f"{rng(r['measured'] / r['pred_high'], r['measured'] / r['pred_low'], '%.2f')}"
              f"{ratio_range} | "
              f"{rng(r['pred_cpu_low'], r['pred_cpu_high'], '%.2g')} | {r['run_cpu']:.2f} | "
              f"{rng(r['run_cpu'] / r['pred_cpu_high'], r['run_cpu'] / r['pred_cpu_low'], '%.2f')} | "
              f"{r['calibration_cpu']:.2f} | "
              f"{'%.2f' % r['cycle_ratio'] if 'cycle_ratio' in r else '–'} |", flush=True)


if __name__ == "__main__":
    main()
