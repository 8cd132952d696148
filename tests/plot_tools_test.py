#!/usr/bin/python3
"""The plot tools (tools/plot_*.py) on small runs: every figure is written as PNG and PDF, bad
input is one line and a non-zero exit, and the closed forms they overlay agree with an
independent evaluation (the Mindlin–Deresiewicz energy against the area between its two
Masing branches integrated numerically).

usage: plot_tools_test.py FRETBEM_BINARY SOURCE_DIR
"""
import os
import subprocess
import sys
import tempfile
import unittest

import numpy as np

BINARY, SOURCE = sys.argv[1], sys.argv[2]
TOOLS = os.path.join(SOURCE, "tools")
sys.path.insert(0, TOOLS)
import fretbem_plot as fp  # noqa: E402

TMP = tempfile.mkdtemp(prefix="fretbem_plots_")


def run(*args):
    return subprocess.run(list(args), capture_output=True, text=True)


def fretbem(scenario, out, *sets):
    cmd = [BINARY, "run", os.path.join(SOURCE, "scenarios", scenario), "--quiet", "--out", out]
    for s in sets:
        cmd += ["--set", s]
    r = run(*cmd)
    assert r.returncode == 0, r.stderr
    return out


def tool(name, *args):
    return run("/usr/bin/python3", os.path.join(TOOLS, name), *args)


class ClosedForms(unittest.TestCase):
    def test_md_energy_is_the_area_between_the_masing_branches(self):
        scn = {"material.E": "210e9", "material.nu": "0.3", "material.mu": "0.5",
               "surface.type": "sphere", "surface.radius": "0.01", "load.normal_force": "10"}
        c = fp.Contact(scn)
        for x in (0.05, 0.3, 0.6, 0.95):
            q_star = x * c.mu * c.P
            u, f = c.md_loop(q_star, points=100001)
            half = len(u) // 2
            # Unloading branch from +Q* then reloading: the loop area is the integral of the
            # gap between the branches over the force.
            area = abs(np.trapz(u[:half], f[:half]) + np.trapz(u[half:], f[half:]))
            self.assertAlmostEqual(c.md_energy(q_star) / area, 1.0, delta=1e-6)

    def test_sliding_shift_matches_cattaneo_at_full_load(self):
        scn = {"material.E": "210e9", "material.nu": "0.3", "material.mu": "0.5",
               "surface.type": "sphere", "surface.radius": "0.01", "load.normal_force": "10"}
        c = fp.Contact(scn)
        delta = c.hertz_radius() ** 2 / c.R  # Hertz approach
        self.assertAlmostEqual(c.md_shift(c.mu * c.P * (1 - 1e-15)) / c.sliding_shift(delta),
                               1.0, delta=1e-6)


class Figures(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.cycle = fretbem("mindlin_cycle.ini", os.path.join(TMP, "cycle"), "grid.n=32",
                            "load.steps_per_cycle=16", "load.cycles=2",
                            "output.fields=state,traction_x", "output.fields_every=4")
        cls.wear = fretbem("fretting_wear.ini", os.path.join(TMP, "wear"), "grid.n=16",
                           "wear.cycles=10", "wear.integrator=cycle")

    def written(self, png):
        for path in (png, os.path.splitext(png)[0] + ".pdf"):
            self.assertTrue(os.path.getsize(path) > 1000, path)

    def test_hysteresis_one_and_several_runs(self):
        out = os.path.join(TMP, "h.png")
        r = tool("plot_hysteresis.py", self.cycle, "--out", out)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.written(out)
        out2 = os.path.join(TMP, "h2.png")
        r = tool("plot_hysteresis.py", self.cycle, self.cycle, "--normalise", "--labels", "a,b",
                 "--cycles", "last", "--out", out2)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.written(out2)

    def test_hysteresis_refuses_a_wear_run_in_one_line(self):
        r = tool("plot_hysteresis.py", self.wear, "--out", os.path.join(TMP, "x.png"))
        self.assertNotEqual(r.returncode, 0)
        self.assertIn("plot_wear.py", r.stderr)
        self.assertEqual(r.stderr.count("\n"), 1)

    def test_fields_wear_and_surface(self):
        for name, args in (("plot_fields.py", [self.cycle]),
                           ("plot_fields.py", [self.cycle, "--field", "traction_x"]),
                           ("plot_wear.py", [self.wear]),
                           ("plot_surface.py", [self.cycle])):
            out = os.path.join(TMP, name + str(len(args)) + ".png")
            r = tool(name, *args, "--out", out)
            self.assertEqual(r.returncode, 0, name + ": " + r.stderr)
            self.written(out)


class WearLoopRows(unittest.TestCase):
    """plot_wear.py --loop-at draws, for cycles.csv's row i, the timeseries rows loop_rows picks:
    checked against what the run itself recorded, the cumulative `dissipation` column."""

    @classmethod
    def setUpClass(cls):
        import plot_wear  # noqa: E402  (tools/ is on the path)
        cls.loop_rows = staticmethod(plot_wear.loop_rows)
        cls.runs = {m: fretbem("fretting_wear.ini", os.path.join(TMP, "loops_" + m), "grid.n=32",
                               "load.steps_per_cycle=16", "wear.integrator=" + m,
                               "wear.cycles=" + n)
                    for m, n in (("cycle", "6"), ("arkode", "200"))}

    def rows_of(self, mode):
        ts = fp.read_csv(os.path.join(self.runs[mode], "timeseries.csv"), "test")
        cy = fp.read_csv(os.path.join(self.runs[mode], "cycles.csv"), "test")
        return ts, cy

    def check_rows(self, mode):
        ts, cy = self.rows_of(mode)
        simulated = np.diff(np.concatenate([[0.0], cy["simulated_cycles"]]))
        kinds = set()
        for i, energy in enumerate(cy["energy_per_cycle"]):
            rows = self.loop_rows(ts["time"], i)
            self.assertGreaterEqual(len(rows), 3, f"row {i}")
            self.assertTrue(np.all(np.floor(ts["time"][rows[1:-1]] + 1e-12) == i), f"row {i}")
            D = ts["dissipation"]
            if abs(simulated[i] - 1.0) < 1e-9:
                # One period continuing the previous row's state (cycle by cycle, a stretch,
                # or ARKODE's continued cycle): from the previous row, which ends at the loop's
                # start loads, the dissipation grows by exactly the cycle's energy.
                start = np.flatnonzero(ts["time"] <= i + 1e-9)[-1]
                self.assertAlmostEqual((D[rows[-1]] - D[start]) / energy, 1.0, delta=1e-12,
                                       msg=f"row {i}")
                kinds.add("period")
            else:
                # ARKODE's steady cycle of a frozen surface, from a fresh state: its loop's
                # start (the first turning point) is not written. A loop at constant normal
                # load under +-Q is odd-symmetric (Masing), so the half-period between its
                # turning points dissipates half the cycle's energy.
                self.assertEqual(len(rows), 3, f"row {i}: the two turning points, closed")
                gained = D[rows[-1]] - D[rows[1]]
                self.assertAlmostEqual(2 * gained / energy, 1.0, delta=1e-9, msg=f"row {i}")
                kinds.add("steady")
        return kinds

    def test_cycle_mode_rows_are_the_cycles_period(self):
        self.assertEqual(self.check_rows("cycle"), {"period"})

    def test_arkode_rows_are_the_cycles_loop(self):
        self.assertEqual(self.check_rows("arkode"), {"period", "steady"})

    def test_loop_figure_at_chosen_n(self):
        out = os.path.join(TMP, "loops.png")
        r = tool("plot_wear.py", self.runs["arkode"], "--loop-at", "0,50,200", "--loop-out", out,
                 "--out", os.path.join(TMP, "wear_arkode.png"))
        self.assertEqual(r.returncode, 0, r.stderr)
        for path in (out, os.path.splitext(out)[0] + ".pdf"):
            self.assertGreater(os.path.getsize(path), 1000)


if __name__ == "__main__":
    unittest.main(argv=[sys.argv[0]], verbosity=1)
