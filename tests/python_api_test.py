#!/usr/bin/python3
"""The Python API (python/module.cpp) against the CLI and closed forms: the same rows as
`fretbem run` to the last digit, fields laid out [ny][nx] as in result.h5 (and a height map
passed as 'xy' equals its transpose passed as 'yx'), errors as exceptions naming the key, the
Ciavarella–Jäger shortcut's force, and the GW model's limits.

usage: python_api_test.py BUILD_PYTHON_DIR FRETBEM_BINARY SOURCE_DIR
"""
import math
import os
import subprocess
import sys
import tempfile
import unittest

import numpy as np

sys.path.insert(0, sys.argv[1])
BINARY, SOURCE = sys.argv[2], sys.argv[3]
import fretbem  # noqa: E402

SCENARIO = os.path.join(SOURCE, "scenarios", "mindlin_cycle.ini")
SMALL = ["grid.n=16", "load.steps_per_cycle=8", "load.cycles=2"]


class Api(unittest.TestCase):
    def test_rows_equal_the_cli_to_the_last_digit(self):
        out = tempfile.mkdtemp(prefix="fretbem_py_")
        cmd = [BINARY, "run", SCENARIO, "--quiet", "--out", out]
        for s in SMALL:
            cmd += ["--set", s]
        subprocess.run(cmd, check=True, capture_output=True)
        with open(os.path.join(out, "timeseries.csv")) as f:
            header = f.readline().strip().split(",")
            cli = [[float(c) for c in line.split(",")] for line in f]
        stepper = fretbem.Stepper(fretbem.Model(fretbem.Scenario.from_file(SCENARIO, SMALL)))
        rows = list(stepper)
        self.assertEqual(len(rows), len(cli))
        for r, c in zip(rows, cli):
            for name, value in zip(header, c):
                if name in ("kx", "normal_residual", "tangential_residual") and math.isnan(value):
                    continue
                self.assertEqual(r[name], value, name)

    def test_fields_are_ny_by_nx_views(self):
        sc = fretbem.Scenario.from_dict({
            "material": {"E": 210e9, "nu": 0.3, "mu": 0.5},
            "grid": {"nx": 24, "ny": 16, "length": 2.8e-4},
            "surface": {"type": "sphere", "radius": 0.01},
            "load": {"normal_force": 10}})
        self.assertEqual(sc.shape, (16, 24))
        model = fretbem.Model(sc)
        stepper = fretbem.Stepper(model)
        row = stepper.advance()
        p = stepper.pressure
        self.assertEqual(p.shape, (16, 24))
        self.assertFalse(p.flags.owndata)  # a view of the solver's field
        # The force is the sum of p h^2, and the sphere's apex is at the centre of the map.
        self.assertAlmostEqual(p.sum() * sc.spacing ** 2 / row["Fz"], 1.0, places=12)
        j, i = np.unravel_index(np.argmax(model.surface), model.surface.shape)
        self.assertEqual((j, i), (7, 11))
        self.assertEqual(stepper.state.dtype, np.uint8)
        self.assertTrue(np.array_equal(stepper.field("pressure"), p))

    def test_height_map_layouts(self):
        base = fretbem.Scenario.from_file(SCENARIO, ["grid.nx=24", "grid.ny=16", "load.path=none"])
        rng = np.random.default_rng(1)
        z = -rng.random((16, 24)) * 1e-9 - np.add.outer(np.arange(16) ** 2, np.arange(24) ** 2) * 1e-9
        a = fretbem.Model(base, surface=z, layout="yx").surface
        b = fretbem.Model(base, surface=z.T.copy(), layout="xy").surface
        self.assertTrue(np.array_equal(a, z))
        self.assertTrue(np.array_equal(b, z))
        with self.assertRaisesRegex(fretbem.InputError, "layout yx"):
            fretbem.Model(base, surface=z.T.copy())  # 24 x 16 given as yx: wrong shape

    def test_errors_name_the_key(self):
        with self.assertRaisesRegex(fretbem.InputError, "material.nu"):
            fretbem.Scenario.from_file(SCENARIO, ["material.nu=0.7"])
        with self.assertRaisesRegex(fretbem.InputError, "grid.n"):
            fretbem.Scenario.from_dict({"material": {"E": 1e9, "nu": 0.3}, "grid": {"n": "x"}})

    def test_ciavarella_jaeger_carries_the_force(self):
        stepper = fretbem.Stepper(fretbem.Model(fretbem.Scenario.from_file(SCENARIO, SMALL)))
        row = stepper.advance()
        sc = fretbem.Scenario.from_file(SCENARIO, SMALL)
        r = fretbem.ciavarella_jaeger(stepper, 0.4 * sc.mu * row["Fz"])
        self.assertAlmostEqual(r["force"] / (0.4 * sc.mu * row["Fz"]), 1.0, places=6)
        self.assertAlmostEqual(r["traction"].sum() * sc.spacing ** 2 / r["force"], 1.0, places=6)

    def test_gw_limits_and_closed_forms(self):
        # eq. 25: k_x/k_x0 = (1 - f)^(1/(1+H)); unloaded it is 1.
        self.assertAlmostEqual(fretbem.gw.stiffness_ratio_fractal(0.0, 0.5), 1.0)
        self.assertAlmostEqual(fretbem.gw.stiffness_ratio_fractal(0.5, 1.0), 0.5 ** 0.5)
        c = fretbem.Contact((210e9, 0.3), mu=0.5, radius=0.01, normal_force=10)
        self.assertAlmostEqual(c.hertz_radius() * 1e6, 68.75, places=1)

    def test_hostile_arguments_raise_and_never_crash(self):
        """Issue 14, session 6 (tools/bench/hostile_hunt.py): Stepper(None) was a SIGSEGV of the
        interpreter; a surface of 1e200 m and NaN written into the surface view ended in
        "residual -nan"; GW stiffness past full sliding was NaN; Contact(radius=-1) complex."""
        sc = fretbem.Scenario.from_file(SCENARIO, SMALL)
        with self.assertRaises(TypeError):
            fretbem.Stepper(None)
        z = np.zeros(sc.shape)
        z[8, 8] = 1e200
        with self.assertRaisesRegex(fretbem.InputError, "heights up to 1e\\+200 m"):
            fretbem.Model(sc, z)
        model = fretbem.Model(sc)
        stepper = fretbem.Stepper(model)
        stepper.advance()
        for view in (model.surface, stepper.pressure, stepper.state):
            with self.assertRaises(ValueError):  # read-only: the solver's own state
                view[0, 0] = np.nan
        self.assertEqual(stepper.advance()["step"], 1)
        with self.assertRaisesRegex(fretbem.InputError, "must be in \\[0, 1\\]"):
            fretbem.gw.stiffness_ratio_fractal(1.5, 0.5)
        with self.assertRaisesRegex(fretbem.InputError, "Hurst"):
            fretbem.gw.stiffness_ratio_fractal(0.5, 0.0)
        with self.assertRaisesRegex(ValueError, "radius"):
            fretbem.Contact((210e9, 0.3), mu=0.5, radius=-1, normal_force=10)
        c = fretbem.Contact((210e9, 0.3), mu=0.5, radius=0.01, normal_force=10)
        with self.assertRaisesRegex(ValueError, "full sliding"):
            c.md_energy(6.0)
        # A message quoting bytes that are not UTF-8 still says what it is about.
        with self.assertRaisesRegex(fretbem.InputError, "invalid line"):
            fretbem.Scenario.from_text(b"\xff\xfe".decode("latin-1"))


if __name__ == "__main__":
    unittest.main(argv=[sys.argv[0]], verbosity=1)
