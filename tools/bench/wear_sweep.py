#!/usr/bin/env python3
"""Wear stress sweep (docs/wear.md, "Stress sweep"): what a user can type, each case checked against its end state.

Every case runs `fretbem run` on a sphere (fretting_wear.ini's by default: 10 N, R = 10 mm,
steel, mu = 0.5) with --set overrides and must end with exit 0 and

  - popov:  partial slip at constant normal force, run far past shakedown (N k_eq >= 1e-6):
            Popov's limit d_inf = P / (2 E* c) + c^2 / (3 R), c = a (1 - Q/mu P)^(1/3), within
            the grid bound |dln d_inf / dln c| h / (2c) (the discrete stick edge is within half a
            cell of c) plus the grid's error on the unworn Hertz indentation a^2/R (row N = 0),
            and no energy dissipated at the end;
  - gross:  gross slip (displacement control past sliding) at constant normal force: the worn
            volume after N cycles is k_eq P N times the slide per cycle, which lies between
            4 (D - U*) and 4 D (U* = 3 mu P (2 - nu) / (16 G a) the tangential shift at which
            a rigid sphere starts sliding on the half-space, Mindlin);
  - ref:    no closed form (varying normal load, rough surface, friction laws, short runs):
            the indentation and max worn depth of the integrator against wear.integrator =
            cycle (the reference) within 10 rtol of the max worn depth, when N <= 2000;
  - refuse: genuinely invalid input: exit 2 and one line on stderr;

and never a crash, hang (timeout), NaN in cycles.csv, or more simulated cycles than N + 1.25
(the final observation is a steady cycle of 1.25); past N = 1e4 the ODE integrators must
simulate at most N / 10, except erk chosen by the user past 50 stability caps, which must say so
in a warning at the run's start. CPU time is the child's user + system time.

    nice -n 10 tools/bench/wear_sweep.py build/fretbem [--grids 32,64] [--filter TEXT] [--list]
    tools/bench/wear_sweep.py build/fretbem --quick      # the ctest subset (WearSweep.Quick)

Prints one markdown row per case and a final count of failures (exit 1 when any).
"""
import argparse
import csv
import math
import os
import re
import resource
import subprocess
import sys
import tempfile

E, NU, P, R, MU = 210e9, 0.3, 10.0, 0.01, 0.5
HERE = os.path.dirname(os.path.abspath(__file__))
SCENARIO = os.path.join(HERE, "..", "..", "scenarios", "fretting_wear.ini")
ROUGH = os.path.join(HERE, "..", "..", "scenarios", "rough_fretting_wear.ini")


def e_star(E2=None, nu2=None):
    inv = (1 - NU * NU) / E + ((1 - nu2 * nu2) / E2 if E2 else 0.0)
    return 1.0 / inv


def hertz_a(es, p=P):
    return (3 * p * R / (4 * es)) ** (1 / 3)


def popov(q, es, p=P):
    a = hertz_a(es, p)
    c = a * (1 - q) ** (1 / 3)
    d = p / (2 * es * c) + c * c / (3 * R)
    return d, c


def sliding_shift(es):
    """Tangential shift at which a rigid sphere starts sliding on the half-space (Mindlin)."""
    G = E / (2 * (1 + NU))
    return 3 * MU * P * (2 - NU) / (16 * G * hertz_a(es))


class Case:
    def __init__(self, name, sets, check, table=None, scenario=SCENARIO, q=None, D=None,
                 es=None):
        self.name, self.sets, self.check, self.table = name, dict(sets), check, table
        self.scenario, self.q, self.D = scenario, q, D
        self.es = es or e_star()


def base(n, length=2.8e-4):
    return {"grid.n": n, "grid.length": length, "wear.rtol": 1e-2}


def cases(grids):
    out = []
    k_law = {"archard": 1.0, "energy": MU}
    for n in grids:
        # Amplitudes x coefficients x laws x integrators, to N k_eq = 1e-6 (past shakedown).
        for q in (0.1, 0.3, 0.6, 0.9, 0.95):
            for law, k in (("archard", 1e-15), ("archard", 1e-13), ("archard", 1e-11),
                           ("energy", 2e-13), ("archard", 1e-10)):
                for integ in (("arkode", "dirk") if n <= 32 else ("arkode",)):
                    N = 1e-6 / (k * k_law[law])
                    if N > 1e6 or N < 10:
                        N = min(max(N, 10), 1e6)
                    s = base(n) | {"load.amplitude": q, "wear.law": law, "wear.coefficient": k,
                                   "wear.cycles": N, "wear.integrator": integ}
                    chk = "popov" if N * k * k_law[law] >= 1e-6 else "sane"
                    out.append(Case(f"n{n} q{q} {law} {k:g} {integ} N{N:g}", s, chk, q=q))
        # Contact 1/2 .. 1/8 of the domain.
        for L in (5.5e-4, 1.1e-3):
            s = base(n, L) | {"load.amplitude": 0.6, "wear.coefficient": 2e-12,
                              "wear.cycles": 5e5}
            out.append(Case(f"n{n} L{L:g} q0.6 N5e5", s, "popov", q=0.6))
        # Explicit integrator and the cycle reference.
        for q in (0.3, 0.9):
            s = base(n) | {"load.amplitude": q, "wear.coefficient": 2e-11, "wear.cycles": 5e4,
                           "wear.integrator": "erk"}
            out.append(Case(f"n{n} q{q} erk N5e4", s, "popov", q=q))
        s = base(n) | {"load.amplitude": 0.6, "wear.coefficient": 2e-11, "wear.cycles": 300,
                       "wear.integrator": "cycle"}
        out.append(Case(f"n{n} q0.6 cycle N300", s, "sane"))
        # Short runs against the reference.
        for N in (10, 100, 1000):
            s = base(n) | {"load.amplitude": 0.6, "wear.coefficient": 1e-11, "wear.cycles": N}
            out.append(Case(f"n{n} q0.6 k1e-11 arkode N{N} (ref)", s, "ref"))
        # Directions.
        for deg in (90, 30):
            s = base(n) | {"load.amplitude": 0.6, "wear.coefficient": 2e-11,
                           "wear.cycles": 5e4, "load.direction": deg}
            out.append(Case(f"n{n} q0.6 direction {deg} N5e4", s, "popov", q=0.6))
        # Two elastic bodies.
        es2 = e_star(70e9, 0.33)
        s = base(n) | {"load.amplitude": 0.6, "wear.coefficient": 2e-11, "wear.cycles": 5e4,
                       "material.E2": 70e9, "material.nu2": 0.33}
        out.append(Case(f"n{n} q0.6 E2=70GPa N5e4", s, "popov", q=0.6, es=es2))
        # Gross slip under displacement control: D = 10 um (~35 U*).
        for law, k, N in (("archard", 1e-15, 1e3), ("archard", 1e-15, 1e4),
                          ("energy", 2e-15, 1e4), ("archard", 1e-13, 100)):
            for integ in ("arkode", "cycle") if N <= 1000 else ("arkode",):
                s = base(n) | {"load.control": "displacement",
                               "load.displacement_amplitude": 1e-5, "wear.law": law,
                               "wear.coefficient": k, "wear.cycles": N, "wear.integrator": integ}
                out.append(Case(f"n{n} gross {law} {k:g} {integ} N{N:g}", s, "gross", D=1e-5))
        # Friction laws.
        s = base(n) | {"load.amplitude": 0.6, "wear.coefficient": 1e-11, "wear.cycles": 1000,
                       "friction.law": "static_kinetic", "friction.mu_kinetic": 0.4}
        out.append(Case(f"n{n} static_kinetic N1000 (ref)", s, "ref"))
        # Evolving friction: cycle mode only (the ODE wear map would restart the evolution in
        # every evaluation; refused below), so no reference but itself.
        s = base(n) | {"load.amplitude": 0.5, "wear.coefficient": 1e-11, "wear.cycles": 1000,
                       "friction.law": "evolving", "friction.mu_final": 0.7,
                       "friction.scale": 1.0, "wear.integrator": "cycle"}
        out.append(Case(f"n{n} evolving cycle N1000", s, "sane"))
        # Periodic grid.
        s = base(n) | {"load.amplitude": 0.6, "wear.coefficient": 2e-11, "wear.cycles": 5e4,
                       "grid.periodic": "true"}
        out.append(Case(f"n{n} periodic q0.6 N5e4", s, "popov", q=0.6))
        # Tables: sine turning points along x, 2-D (circle-like), varying normal load.
        out.append(Case(f"n{n} table x N5e4",
                        base(n) | {"load.path": "table", "wear.coefficient": 2e-11,
                                   "wear.cycles": 5e4},
                        "popov", q=0.6, table="time,Fx\n0,0\n0.25,3\n0.5,0\n0.75,-3\n1,0\n"))
        # 2-D motion: cycle mode only (the ODE integrators refuse it, below).
        out.append(Case(f"n{n} table 2-D cycle N1000",
                        base(n) | {"load.path": "table", "wear.coefficient": 1e-11,
                                   "wear.cycles": 1000, "wear.integrator": "cycle"},
                        "sane", table="time,Fx,Fy\n0,0,0\n1,2,1\n2,0,2\n3,-2,1\n4,0,0\n"))
        out.append(Case(f"n{n} table varying Fz N1000 (ref)",
                        base(n) | {"load.path": "table", "wear.coefficient": 1e-11,
                                   "wear.cycles": 1000},
                        "ref", table="time,Fz,Fx\n0,10,0\n1,12,3\n2,8,0\n3,12,-3\n4,10,0\n"))
        out.append(Case(f"n{n} table varying Fz N1e5",
                        base(n) | {"load.path": "table", "wear.coefficient": 1e-11,
                                   "wear.cycles": 1e5},
                        "sane", table="time,Fz,Fx\n0,10,0\n1,12,3\n2,8,0\n3,12,-3\n4,10,0\n"))
        out.append(Case(f"n{n} table delta+Ux gross N1000",
                        base(n) | {"load.path": "table", "load.control": "displacement",
                                   "wear.coefficient": 1e-15, "wear.cycles": 1000},
                        "sane",
                        table="time,delta,Ux\n0,4.7e-7,0\n1,4.7e-7,1e-5\n2,4.7e-7,-1e-5\n"
                              "3,4.7e-7,0\n"))
        # Rough surface (rough_fretting_wear.ini).
        for N in (1000, 1e5):
            out.append(Case(f"n{n} rough N{N:g}", {"grid.n": n, "wear.cycles": N},
                            "ref" if N <= 1000 else "sane", scenario=ROUGH))
    # Invalid input: one line, exit 2.
    out.append(Case("refuse amplitude 1.0", base(32) | {"load.amplitude": 1.0}, "refuse"))
    out.append(Case("refuse wear.cycles 0.5", base(32) | {"wear.cycles": 0.5}, "refuse"))
    out.append(Case("refuse ramp", base(32) | {"load.path": "ramp"}, "refuse"))
    out.append(Case("refuse evolving friction with arkode",
                    base(32) | {"friction.law": "evolving", "friction.mu_final": 0.7,
                                "friction.scale": 1.0}, "refuse"))
    out.append(Case("refuse 2-D table with arkode",
                    base(32) | {"load.path": "table", "wear.cycles": 1000}, "refuse",
                    table="time,Fx,Fy\n0,0,0\n1,2,1\n2,0,2\n3,-2,1\n4,0,0\n"))
    out.append(Case("refuse cycle N 10.5",
                    base(32) | {"wear.cycles": 10.5, "wear.integrator": "cycle"}, "refuse"))
    return out


# The ctest subset (WearSweep.Quick), cheap cases at n = 32 through the CLI: near sliding to
# Popov's end state (the normal-solver cycle), a short run against cycle, and the refusals
# (evolving friction, 2-D tables). The other failures the sweep found have gtests
# (WearPaths.ShortCapGrossSlipCostsAtMostEveryCycle, WearPaths.RowIndentationAtThePeriodEnd).
QUICK = {
    "n32 q0.9 archard 1e-11 arkode N100000",
    "n32 q0.6 k1e-11 arkode N10 (ref)",
    "refuse amplitude 1.0",
    "refuse evolving friction with arkode",
    "refuse 2-D table with arkode",
}


def cpu_children():
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def run(binary, case, integrator=None, timeout=1800):
    """Runs the case; returns (returncode, stderr, rows, cpu seconds, integrator stats)."""
    with tempfile.TemporaryDirectory() as out:
        sets = dict(case.sets)
        if integrator:
            sets["wear.integrator"] = integrator
        scenario = case.scenario
        if case.table:
            path = os.path.join(out, "table.csv")
            with open(path, "w") as f:
                f.write(case.table)
            sets["load.table"] = path
            header = case.table.split("\n", 1)[0].split(",")
            if "Fz" in header or "delta" in header:
                # The table drives the normal load: a constant normal-load key beside it is
                # refused (one line, exit 2), and --set cannot remove a key, so run a copy of
                # the scenario without it.
                scenario = os.path.join(out, "scenario.ini")
                with open(case.scenario) as f, open(scenario, "w") as g:
                    g.writelines(x for x in f if not re.match(r"\s*normal_force\s*=", x))
        # --quiet only for refusals (one line on stderr); otherwise the summary line on stdout
        # gives the integrator's steps and Newton failures.
        args = [binary, "run", scenario, "--out", os.path.join(out, "o")]
        if case.check == "refuse":
            args.append("--quiet")
        for key, v in sets.items():
            args += ["--set", f"{key}={v}"]
        c0 = cpu_children()
        try:
            proc = subprocess.run(args, capture_output=True, text=True, timeout=timeout)
        except subprocess.TimeoutExpired:
            return None, "timeout", [], cpu_children() - c0, ""
        cpu = cpu_children() - c0
        rows = []
        f = os.path.join(out, "o", "cycles.csv")
        if proc.returncode == 0 and os.path.exists(f):
            rows = list(csv.DictReader(open(f)))
        m = re.search(r"(\d+) (implicit|explicit)[^,]* steps, (\d+) error-test failures, "
                      r"(\d+) Newton failures; (\d+) stretches", proc.stdout)
        stats = f"{m[1]} {m[2][:4]} steps, {m[3]} err, {m[4]} Newton fails, {m[5]} stretches" \
            if m else ""
        return proc.returncode, proc.stderr.strip(), rows, cpu, stats


def finite(rows):
    return all(math.isfinite(float(v)) for r in rows for v in r.values() if v not in ("", None))


def judge(binary, case):
    rc, err, rows, cpu, stats = run(binary, case)
    N = float(case.sets.get("wear.cycles", 0))
    if case.check == "refuse":
        ok = rc == 2 and err.count("\n") == 0 and len(err) > 0
        return ok, N, float("nan"), cpu, f"exit {rc}: {err[:100]}"
    if rc != 0:
        return False, N, float("nan"), cpu, f"exit {rc}: {err.splitlines()[-1][:160] if err else ''}"
    if not rows or not finite(rows):
        return False, N, float("nan"), cpu, "no rows or non-finite value in cycles.csv"
    last = rows[-1]
    sim = float(last["simulated_cycles"])
    problems = []
    problems_note = ""
    if float(last["N"]) != N:
        problems.append(f"ended at N = {last['N']}")
    integ = case.sets.get("wear.integrator", "arkode")
    if sim > N + 1.25:
        problems.append(f"simulated {sim} > N + 1.25")
    if integ != "cycle" and N >= 1e4 and sim > N / 10:
        # erk chosen by the user keeps its stability cap; the run must say so at its start.
        if integ == "erk" and "warning: wear.integrator = erk" in err:
            problems_note = f"simulated {sim:.1f} > N/10, warned (erk's stability cap)"
        else:
            problems.append(f"simulated {sim} > N/10")
    note = ""
    if case.check == "popov":
        d_inf, c = popov(case.q, case.es)
        h = float(case.sets["grid.length"]) / float(case.sets["grid.n"])
        dlnd = abs((-P / (2 * case.es * c) + 2 * c * c / (3 * R)) / d_inf)
        bound = dlnd * h / (2 * c)
        e = float(last["delta"]) / d_inf - 1
        # The grid's own error on the unworn contact (discrete Hertz indentation against a^2/R)
        # is not the wear engine's and carries over to the end state's indentation.
        a = hertz_a(case.es)
        hertz = abs(float(rows[0]["delta"]) / (a * a / R) - 1)
        bound += hertz
        energy = float(last["energy_per_cycle"]) / max(float(rows[0]["energy_per_cycle"]), 1e-300)
        note = f"d/d_inf-1 = {e:+.4f} (bound {bound:.3f}), energy end/first {energy:.1e}"
        if abs(e) > bound:
            problems.append("end state off Popov")
        if energy > 1e-3:
            problems.append("still dissipating")
    elif case.check == "gross":
        k = float(case.sets["wear.coefficient"])
        k_eq = k * (MU if case.sets.get("wear.law") == "energy" else 1.0)
        # The final row observes the surface worn by N cycles.
        slide = float(last["wear_volume"]) / (k_eq * P * N)
        lo, hi = 4 * (case.D - sliding_shift(case.es)), 4 * case.D
        note = f"slide/cycle {slide:.4g} m in [{lo:.4g}, {hi:.4g}]"
        if not (0.995 * lo <= slide <= 1.005 * hi):
            problems.append("gross-slip rate off the closed form")
    elif case.check == "ref" and N <= 2000 and integ != "cycle":
        rc2, err2, ref, _, _ = run(binary, case, "cycle")
        if rc2 != 0 or not ref:
            problems.append(f"reference failed: {err2[:100]}")
        else:
            wmax = max(float(ref[-1]["max_worn_depth"]), 1e-300)
            dd = abs(float(last["delta"]) - float(ref[-1]["delta"])) / wmax
            dw = abs(float(last["max_worn_depth"]) - wmax) / wmax
            rtol = float(case.sets.get("wear.rtol", 1e-3))
            note = f"vs cycle: delta {dd:.2e}, max depth {dw:.2e} of max depth"
            if dd > 10 * rtol or dw > 10 * rtol:
                problems.append("off the cycle reference")
    return not problems, N, sim, cpu, "; ".join(
        problems + [x for x in (problems_note, note, stats) if x])


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("binary", nargs="?", default="build/fretbem")
    ap.add_argument("--grids", default="32")
    ap.add_argument("--filter", default="")
    ap.add_argument("--list", action="store_true")
    ap.add_argument("--quick", action="store_true",
                    help="the ctest subset: QUICK cases at n = 32 (a few s of CPU)")
    a = ap.parse_args()
    todo = [c for c in cases([int(v) for v in a.grids.split(",")]) if a.filter in c.name]
    if a.quick:
        todo = [c for c in cases([32]) if c.name in QUICK]
    if a.list:
        for c in todo:
            print(c.name)
        return 0
    print("| case | N | simulated cycles | CPU (s) | result |")
    print("|---|---|---|---|---|")
    failures = 0
    for c in todo:
        ok, N, sim, cpu, note = judge(a.binary, c)
        failures += not ok
        print(f"| {c.name} | {N:g} | {sim:.1f} | {cpu:.1f} | {'ok' if ok else 'FAIL'}: {note} |",
              flush=True)
    print(f"{failures} failures in {len(todo)} cases; load average {os.getloadavg()[0]:.1f}")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
