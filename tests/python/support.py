"""Shared by the Python output tests: a small run of scenarios/mindlin_cycle.ini, and failed
checks collected, each printed, with a non-zero exit at the end (one run reports every
failure, not only the first)."""
import os
import subprocess
import sys

FAILURES = []


def check(cond, what):
    if not cond:
        FAILURES.append(what)
        print("FAIL:", what)


def finish():
    """Exits 1 naming the count of failed checks, else prints ok and exits 0."""
    if FAILURES:
        sys.exit(f"{len(FAILURES)} check(s) failed")
    print("ok")
    sys.exit(0)


# The small run's grid (rectangular, so that x and y cannot be confused), normal force (N)
# and steps per cycle (one cycle of a force-controlled sine, turning points at steps 2 and 6).
NX, NY, LENGTH, FZ, STEPS = 16, 12, 3e-4, 10.0, 8


def run_small(fretbem, source, out, fields):
    """mindlin_cycle.ini on the grid above for one cycle, saving `fields`, into `out`."""
    sets = {"grid.nx": NX, "grid.ny": NY, "grid.length": LENGTH, "load.normal_force": FZ,
            "load.cycles": 1, "load.steps_per_cycle": STEPS, "output.fields": fields}
    cmd = [fretbem, "run", os.path.join(source, "scenarios", "mindlin_cycle.ini")]
    for key, value in sets.items():
        cmd += ["--set", f"{key}={value}"]
    subprocess.run(cmd + ["--out", out, "--quiet"], check=True)
