#!/usr/bin/env python3
"""Cost of fretbem against the grid size n (docs/performance.md, "Scaling with the grid").

For each n: `fretbem check` (its memory and cost estimate) and `fretbem run` of a
Mindlin-Deresiewicz cycle (scenarios/mindlin_cycle.ini, 1 and 2 cycles: the steady cycle is the
difference), a rough fretting cycle (scenarios/rough_fretting_cycle.ini, 1 and 2 cycles) and a
short rough wear run (scenarios/rough_fretting_wear.ini, small wear.cycles). Per run: CPU seconds
(user + system of the child, os.wait4, so other load on the machine does not inflate it), wall
seconds, peak resident memory of the child (ru_maxrss), FFT convolutions and solver iterations
(timeseries.csv). At n >= 512 also solver.threads = 2. Beyond --max-n only check's estimates.
Fits iterations per solve ~ n^a and CPU ~ n^2 log n * n^b by least squares in log-log.

    /usr/bin/python3 tools/bench/scaling.py [--binary build/fretbem] [--out scaling.md]
        [--ns 64,128,256,512] [--wear-max-n 512] [--check-n 2048,4096] [--budget SECONDS]
        [--cases mindlin,rough,wear] [--threads 1,2] [--wear-cycles 100] [--no-estimate]
        [--stop-after N] [--quick]

--cases picks the cases by name (a name selects its 2-cycle run too, "mindlin 1" only the
first cycle: "mindlin 1,rough 1" for one cycle each at large n); --threads overrides the thread
counts (default 1, and 1,2 from n = 512); --no-estimate skips check's cost calibration (its
memory estimate stays), which at n >= 1024 costs minutes; --stop-after N runs the first N steps
of each run alone (`fretbem run --stop-after`: a contiguous first part where a whole run takes
too long, e.g. the first reversal of a Mindlin cycle at n = 2048).

--quick (n = 32, 64, no estimates beyond) is the smoke test registered in tests/CMakeLists.txt.
Runs that would start after --budget seconds are skipped and listed as skipped.
"""
import argparse
import csv
import math
import os
import re
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

# name, scenario, overrides for "one cycle", smallest n that gets a 2-thread run
CASES = [
    ("mindlin", "mindlin_cycle.ini", ["load.cycles=1"]),
    ("mindlin 2cyc", "mindlin_cycle.ini", ["load.cycles=2"]),
    ("rough", "rough_fretting_cycle.ini", ["load.cycles=1"]),
    ("rough 2cyc", "rough_fretting_cycle.ini", ["load.cycles=2"]),
    ("wear", "rough_fretting_wear.ini", ["wear.cycles=100"]),
]
THREADS_FROM_N = 512


def selected_cases(names, wear_cycles):
    """The CASES named in the comma list `names` (all when empty); "NAME 1" is its first cycle
    alone. The wear case runs wear_cycles cycles."""
    wanted = [x.strip() for x in names.split(",") if x.strip()]
    known = {c[0] for c in CASES}
    for w in wanted:
        if w.removesuffix(" 1") not in known:
            sys.exit(f"scaling.py: --cases: unknown case '{w}' (known: {', '.join(sorted(known))})")
    out = []
    for name, ini, sets in CASES:
        base = name.removesuffix(" 2cyc")
        if wanted and base not in wanted and not (name == base and base + " 1" in wanted):
            continue
        if name == "wear":
            sets = [f"wear.cycles={wear_cycles}"]
        out.append((name, ini, sets))
    return out


def timed_run(cmd):
    """Runs cmd; returns (exit code, output, CPU s, wall s, peak RSS MiB) of that child alone."""
    start = time.monotonic()
    p = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    out = p.stdout.read()
    _, status, ru = os.wait4(p.pid, 0)
    wall = time.monotonic() - start
    # ru_maxrss is in KiB on Linux (getrusage(2)).
    return (os.waitstatus_to_exitcode(status), out, ru.ru_utime + ru.ru_stime, wall,
            ru.ru_maxrss / 1024.0)


def check_estimate(binary, scenario, sets, estimate=True):
    """fretbem check: (memory MiB, convolutions, CPU s) as it predicts them; None if absent."""
    cmd = [binary, "check", scenario] + [a for s in sets for a in ("--set", s)]
    if not estimate:
        cmd.append("--no-estimate")
    out = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True).stdout
    mem = re.search(r"memory: about ([0-9.e+]+) (KiB|MiB|GiB)", out)
    mib = None
    if mem:
        mib = float(mem.group(1)) * {"KiB": 1 / 1024, "MiB": 1, "GiB": 1024}[mem.group(2)]
    cost = re.search(r"cost: about ([0-9.e+]+) FFT convolutions, ([0-9.e+]+) s of CPU", out)
    conv, cpu = (float(cost.group(1)), float(cost.group(2))) if cost else (None, None)
    # Wear runs: "cost: about LOW to HIGH s of CPU"; the upper end is the guard's figure.
    wear = re.search(r"cost: about [0-9.e+]+ to ([0-9.e+]+) s of CPU", out)
    if wear:
        cpu = float(wear.group(1))
    return mib, conv, cpu


def timeseries_counts(path):
    """(solves, convolutions, mean normal iterations, mean tangential iterations) per step."""
    steps = conv = nit = tit = 0
    with open(path) as f:
        for row in csv.DictReader(f):
            steps += 1
            conv += float(row["convolutions"])
            nit += float(row["normal_iterations"])
            tit += float(row["tangential_iterations"])
    steps = max(steps, 1)
    return steps, conv, nit / steps, tit / steps


def measure(binary, scenario, sets, workdir, stop_after=None):
    out_dir = os.path.join(workdir, "run")
    cmd = [binary, "run", scenario, "--out", out_dir, "--overwrite", "--quiet"]
    if stop_after:
        cmd += ["--stop-after", str(stop_after)]
    cmd += [a for s in sets for a in ("--set", s)]
    code, text, cpu, wall, rss = timed_run(cmd)
    if code != 0:
        raise RuntimeError(f"{' '.join(cmd)} exited {code}: {text.strip()}")
    row = {"cpu": cpu, "wall": wall, "rss": rss}
    ts = os.path.join(out_dir, "timeseries.csv")
    if os.path.exists(ts):
        row["steps"], row["conv"], row["nit"], row["tit"] = timeseries_counts(ts)
    return row


def fit_power(ns, ys):
    """Least-squares exponent a of y ~ c n^a (log-log)."""
    pts = [(math.log(n), math.log(y)) for n, y in zip(ns, ys) if y and y > 0]
    if len(pts) < 2:
        return None
    mx = sum(p[0] for p in pts) / len(pts)
    my = sum(p[1] for p in pts) / len(pts)
    sxx = sum((p[0] - mx) ** 2 for p in pts)
    return sum((p[0] - mx) * (p[1] - my) for p in pts) / sxx


def fmt(v, spec=".3g"):
    return "-" if v is None else format(v, spec)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--binary", default=os.path.join(ROOT, "build", "fretbem"))
    ap.add_argument("--out", default=None, help="markdown file for the table (default stdout)")
    ap.add_argument("--ns", default="64,128,256,512,1024")
    ap.add_argument("--wear-max-n", type=int, default=512)
    ap.add_argument("--check-n", default="2048,4096")
    ap.add_argument("--budget", type=float, default=900.0)
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--cases", default="", help="names of the cases to run (default all)")
    ap.add_argument("--threads", default="", help="thread counts (default 1; 1,2 from n = 512)")
    ap.add_argument("--wear-cycles", default="100", help="wear.cycles of the wear case")
    ap.add_argument("--no-estimate", action="store_true", help="skip check's cost calibration")
    ap.add_argument("--stop-after", type=int, default=None,
                    help="run the first N steps of each run only (fretbem run --stop-after)")
    args = ap.parse_args()
    cases = selected_cases(args.cases, args.wear_cycles)
    threads_for = (lambda n: [int(t) for t in args.threads.split(",")]) if args.threads else (
        lambda n: [1, 2] if n >= THREADS_FROM_N else [1])
    ns = [32, 64] if args.quick else [int(x) for x in args.ns.split(",")]
    check_ns = [] if args.quick else [int(x) for x in args.check_n.split(",") if x]
    t0 = time.monotonic()
    lines = ["| case | n | threads | CPU s | wall s | peak MiB | check MiB | check CPU s | "
             "solves | conv | conv/solve | normal it | tang it |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    results, skipped = {}, []
    with tempfile.TemporaryDirectory() as work:
        for n in ns:
            for name, ini, sets in cases:
                if name == "wear" and n > args.wear_max_n:
                    continue
                for threads in threads_for(n):
                    label = f"{name} n={n} threads={threads}"
                    if time.monotonic() - t0 > args.budget:
                        skipped.append(label)
                        continue
                    all_sets = sets + [f"grid.n={n}", f"solver.threads={threads}"]
                    scenario = os.path.join(ROOT, "scenarios", ini)
                    est = check_estimate(args.binary, scenario, all_sets,
                                         estimate=threads == 1 and "2cyc" not in name
                                         and not args.no_estimate)
                    row = measure(args.binary, scenario, all_sets, work, args.stop_after)
                    row["est"] = est
                    results[(name, n, threads)] = row
                    cps = row["conv"] / row["steps"] if "conv" in row else None
                    lines.append(
                        f"| {name} | {n} | {threads} | {row['cpu']:.3g} | {row['wall']:.3g} | "
                        f"{row['rss']:.0f} | {fmt(est[0], '.0f')} | {fmt(est[2])} | "
                        f"{row.get('steps', '-')} | {fmt(row.get('conv'), '.0f')} | "
                        f"{fmt(cps)} | {fmt(row.get('nit'))} | {fmt(row.get('tit'))} |")
                    print(lines[-1], flush=True)
        for n in check_ns:
            for name, ini, sets in [c for c in cases if "2cyc" not in c[0]]:
                if time.monotonic() - t0 > args.budget:
                    skipped.append(f"check {name} n={n}")
                    continue
                est = check_estimate(args.binary, os.path.join(ROOT, "scenarios", ini),
                                     sets + [f"grid.n={n}"], estimate=name != "wear")
                lines.append(f"| {name} (check only) | {n} | 1 | - | - | - | {fmt(est[0], '.0f')}"
                             f" | {fmt(est[2])} | - | {fmt(est[1], '.0f')} | - | - | - |")
                print(lines[-1], flush=True)
    lines.append("")
    lines += steady_and_fits(results, ns)
    if skipped:
        lines.append("skipped (over the time budget): " + ", ".join(skipped))
    text = "\n".join(lines) + "\n"
    if args.out:
        with open(args.out, "w") as f:
            f.write(text)
    print(text)
    return 0 if results else 1


def steady_and_fits(results, ns):
    """Steady-cycle cost (2 cycles - 1 cycle) and the power-law fits."""
    out = []
    for base in ("mindlin", "rough"):
        sn, cpu, its = [], [], []
        for n in ns:
            one, two = results.get((base, n, 1)), results.get((base + " 2cyc", n, 1))
            if not one or not two:
                continue
            d_cpu = two["cpu"] - one["cpu"]
            d_steps = two["steps"] - one["steps"]
            d_it = (two["tit"] * two["steps"] - one["tit"] * one["steps"]) / max(d_steps, 1)
            out.append(f"{base} steady cycle n={n}: CPU {d_cpu:.3g} s, {d_steps} steps, "
                       f"{(two['conv'] - one['conv']):.0f} convolutions, "
                       f"{d_it:.3g} tangential iterations per solve")
            sn.append(n)
            cpu.append(d_cpu / (n * n * math.log(n)))
            its.append(d_it)
        a, b = fit_power(sn, its), fit_power(sn, cpu)
        out.append(f"{base} fit: tangential iterations per solve ~ n^{fmt(a, '.2f')}, "
                   f"steady-cycle CPU ~ n^2 log n * n^{fmt(b, '.2f')} (n = {sn})")
    for base in ("mindlin", "rough", "wear"):
        sn = [n for n in ns if (base, n, 1) in results]
        its = [results[(base, n, 1)].get("tit") for n in sn]
        cpu = [results[(base, n, 1)]["cpu"] / (n * n * math.log(n)) for n in sn]
        if sn:
            out.append(f"{base} one run fit: tangential iterations per step ~ "
                       f"n^{fmt(fit_power(sn, its), '.2f')}, CPU ~ n^2 log n * "
                       f"n^{fmt(fit_power(sn, cpu), '.2f')} (n = {sn})")
    out.append("")
    return out


if __name__ == "__main__":
    sys.exit(main())
