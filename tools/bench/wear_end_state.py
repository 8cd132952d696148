#!/usr/bin/env python3
"""Bench: the end state of partial-slip fretting wear against Popov's closed form
(docs/wear.md, "Accuracy and end states").

Sphere of fretting_wear.ini (10 N, R = 10 mm, steel, mu = 0.5) under Q = q mu P, every case
run to N k_eq = 1e-6 (far past shakedown). Closed form (Popov, Sci. Rep. 4:3749, 2014):
c = a (1 - q)^(1/3), d_inf = P / (2 E* c) + c^2 / (3 R), the contact shrinks onto the stick
disc and dissipates nothing. Prints a markdown table (docs/wear.md):

    tools/bench/wear_end_state.py build/fretbem [n ...]
"""
import csv
import math
import os
import subprocess
import sys
import tempfile
import time

E, NU, P, R = 210e9, 0.3, 10.0, 0.01


def closed_form(q):
    es = E / (1 - NU * NU)
    a = (3 * P * R / (4 * es)) ** (1 / 3)
    c = a * (1 - q) ** (1 / 3)
    return P / (2 * es * c) + c * c / (3 * R), c


def run(binary, n, q, law, k, integrator, nk=1e-6):
    k_eq = k * (0.5 if law == "energy" else 1.0)
    N = nk / k_eq
    scenario = os.path.join(os.path.dirname(__file__), "..", "..", "scenarios", "fretting_wear.ini")
    with tempfile.TemporaryDirectory() as out:
        sets = {"grid.n": n, "load.amplitude": q, "wear.law": law, "wear.coefficient": k,
                "wear.cycles": N, "wear.integrator": integrator, "wear.rtol": 1e-2}
        args = [binary, "run", scenario, "--quiet", "--out", out]
        for key, v in sets.items():
            args += ["--set", f"{key}={v}"]
        t0 = time.time()
        proc = subprocess.run(args, capture_output=True, text=True)
        wall = time.time() - t0
        if proc.returncode != 0:
            return f"| {n} | {q} | {law} {k:g} | {integrator} | {N:g} | failed: {proc.stderr.strip()} |"
        rows = list(csv.DictReader(open(os.path.join(out, "cycles.csv"))))
    d_inf, c = closed_form(q)
    last = rows[-1]
    return (f"| {n} | {q} | {law} {k:g} | {integrator} | {N:g} | {float(last['simulated_cycles']):.1f} "
            f"| {wall:.1f} | {float(last['delta']) / d_inf - 1:+.4f} "
            f"| {float(last['contact_radius']) / c - 1:+.3f} "
            f"| {float(last['energy_per_cycle']) / float(rows[0]['energy_per_cycle']):.1e} |")


def main():
    binary = sys.argv[1] if len(sys.argv) > 1 else "build/fretbem"
    grids = [int(v) for v in sys.argv[2:]] or [64]
    print("| n | Q/muP | law, coefficient (1/Pa) | integrator | N | simulated cycles | wall (s) "
          "| d/d_inf - 1 | r_contact/c - 1 | energy end/first |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for n in grids:
        for law in ("archard", "energy"):
            for q in (0.3, 0.6, 0.9):
                for k in (2e-13, 2e-11):
                    print(run(binary, n, q, law, k, "arkode"), flush=True)
    print(f"load average: {os.getloadavg()[0]:.1f}")


if __name__ == "__main__":
    main()
