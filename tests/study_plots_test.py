#!/usr/bin/python3
"""The study plot tools (tools/plot_energy_per_cycle.py, tools/plot_fig3_contact_fraction.py) on
tiny sweeps: figures written as PNG and PDF, bad input one line and a non-zero exit. Separate
from plot_tools_test.py so that each ctest entry stays well inside its time limit.

usage: study_plots_test.py FRETBEM_BINARY SOURCE_DIR
"""
import os
import sys
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from plot_tools_test import TMP, SOURCE, BINARY, png_size, run, tool  # noqa: E402


class StudyFigures(unittest.TestCase):
    """The study plot tools on tiny sweeps (n = 32): figures written, bad input one line."""

    def sweep(self, name, scenario, vary, *sets):
        d = os.path.join(TMP, name)
        os.makedirs(d, exist_ok=True)
        study = os.path.join(d, "study.ini")
        with open(study, "w") as f:
            f.write(f"[study]\nscenario = {os.path.join(SOURCE, 'scenarios', scenario)}\n"
                    f"out = {os.path.join(d, 'out')}\n")
            f.writelines(f"set = {s}\n" for s in sets)
            f.write(f"[vary]\n{vary}")
        r = run(BINARY, "sweep", study, "--quiet")
        self.assertEqual(r.returncode, 0, r.stderr)
        return os.path.join(d, "out")

    def sized_for_panels(self, png):
        # Two panels side by side: a landscape page wide at most (12 in at 200 dpi), no strip
        # (such as 16.8 x 3.2 in, 3360 x 640 px).
        w, h = png_size(png)
        self.assertLessEqual(w, 2400, png)
        self.assertLessEqual(w / h, 3.2, png)

    def test_energy_per_cycle_sphere_and_rough(self):
        sphere = self.sweep("epc", "mindlin_cycle.ini", "load.amplitude = 0.3, 0.8\n",
                            "grid.n=32", "load.cycles=1", "load.steps_per_cycle=16",
                            "output.fields=none")
        r = tool("plot_energy_per_cycle.py", sphere)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertTrue(os.path.getsize(os.path.join(sphere, "energy_per_cycle.pdf")) > 1000)
        self.sized_for_panels(os.path.join(sphere, "energy_per_cycle.png"))
        rough = self.sweep("epcr", "rough_fretting_cycle.ini",
                           "surface.seed = 1, 2\nload.amplitude = 0.3, 0.6\n", "grid.n=32",
                           "load.cycles=1", "load.steps_per_cycle=8")
        r = tool("plot_energy_per_cycle.py", rough)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertTrue(os.path.getsize(os.path.join(rough, "energy_per_cycle.png")) > 1000)

    def test_fig3_contact_fraction(self):
        out = self.sweep("fig3", "rough_monotone.ini", "load.normal_force = 60, 300\n",
                         "grid.n=32", "load.steps=8")
        r = tool("plot_fig3_contact_fraction.py", out)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertTrue(os.path.getsize(os.path.join(out, "fig3_contact_fraction.pdf")) > 1000)
        self.sized_for_panels(os.path.join(out, "fig3_contact_fraction.png"))

    def test_no_sweep_is_one_line(self):
        for name in ("plot_energy_per_cycle.py", "plot_fig3_contact_fraction.py"):
            r = tool(name, os.path.join(TMP, "no_such_study"))
            self.assertNotEqual(r.returncode, 0)
            self.assertIn("sweep.csv", r.stderr)
            self.assertEqual(r.stderr.count("\n"), 1, r.stderr)



if __name__ == "__main__":
    unittest.main(argv=[sys.argv[0]], verbosity=1)
