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


if __name__ == "__main__":
    unittest.main(argv=[sys.argv[0]], verbosity=1)
