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


def cli_table(name):
    """`fretbem run SCENARIO` with SMALL: the header and rows of its output file `name`."""
    out = tempfile.mkdtemp(prefix="fretbem_py_")
    cmd = [BINARY, "run", SCENARIO, "--quiet", "--out", out]
    for s in SMALL:
        cmd += ["--set", s]
    subprocess.run(cmd, check=True, capture_output=True)
    with open(os.path.join(out, name)) as f:
        header = f.readline().strip().split(",")
        return header, [[float(c) for c in line.split(",")] for line in f]


class Api(unittest.TestCase):
    def test_rows_equal_the_cli_to_the_last_digit(self):
        header, cli = cli_table("timeseries.csv")
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
        self.assertAlmostEqual(c.contact_radius * 1e6, 68.75, places=1)

    def test_compiled_sphere_forms_equal_the_numpy_contact(self):
        # One C++ home (fretbem.sphere) and the pure-numpy Contact the plot tools load without
        # the compiled module: the same Johnson formulas, equal to rounding.
        c = fretbem.Contact((210e9, 0.3), mu=0.5, radius=0.01, normal_force=10)
        s = fretbem.sphere
        a = s.hertz_contact_radius(10, 0.01, c.E_star)
        self.assertAlmostEqual(a / c.hertz_radius(), 1.0, places=12)
        self.assertAlmostEqual(s.hertz_peak_pressure(10, a) / c.hertz_peak_pressure(), 1.0,
                               places=12)
        delta = s.hertz_approach(a, 0.01)
        self.assertAlmostEqual(delta / c.hertz_indentation(), 1.0, places=12)
        us = s.full_sliding_shift(0.5, delta, c.E_star, c.G_star)
        self.assertAlmostEqual(us / c.sliding_shift(delta), 1.0, places=12)
        Q = 0.6 * 0.5 * 10
        self.assertAlmostEqual(a * s.cattaneo_stick_ratio(0.6) / c.stick_radius(Q), 1.0,
                               places=12)
        self.assertAlmostEqual(us * s.cattaneo_shift_ratio(0.6) / float(c.md_shift(Q)), 1.0,
                               places=12)
        self.assertAlmostEqual(
            s.mindlin_energy_per_cycle(0.6, 0.5, 10, us) / float(c.md_energy(Q)), 1.0, places=12)

    def test_cycles_equal_cycles_csv(self):
        header, cli = cli_table("cycles.csv")
        stepper = fretbem.Stepper(fretbem.Model(fretbem.Scenario.from_file(SCENARIO, SMALL)))
        rows = list(stepper)
        self.assertEqual(header, fretbem.cycle_columns)
        self.assertEqual(len(stepper.cycles), 2)
        for mine, theirs in zip(stepper.cycles, cli):
            self.assertEqual([mine[c] for c in header], theirs)
        self.assertTrue(np.array_equal(stepper.cycles_array(), np.array(cli)))
        # Energy per cycle: the cumulative dissipation's increase over the cycle's steps
        # (8 per cycle after the normal loading, row 0).
        for k, c in enumerate(stepper.cycles):
            gained = rows[8 * (k + 1)]["dissipation"] - rows[8 * k]["dissipation"]
            self.assertAlmostEqual(c["dissipated_energy"] / gained, 1.0, places=12)

    def test_cycles_of_a_ramp_are_none(self):
        stepper = fretbem.Stepper(fretbem.Model(fretbem.Scenario.from_file(
            os.path.join(SOURCE, "scenarios", "cattaneo.ini"), ["grid.n=16", "load.steps=4"])))
        list(stepper)
        self.assertEqual(stepper.cycles, [])
        self.assertEqual(stepper.cycles_array().shape, (0, len(fretbem.cycle_columns)))

    def test_from_dict_takes_python_types(self):
        sc = fretbem.Scenario.from_dict({
            "material": {"E": 210e9, "nu": 0.3, "mu": np.float64(0.5)},
            "grid": {"n": 32.0, "length": 2.8e-4, "periodic": False},
            "surface": {"type": "sphere", "radius": 0.01},
            "load": {"normal_force": np.int64(10), "path": "sine", "amplitude": 0.5},
            "output": {"fields": ["pressure", "state"]}})
        self.assertEqual(sc.shape, (32, 32))
        self.assertIn("fields = pressure, state", sc.text)
        self.assertIn("mu = 0.5", sc.text)
        with self.assertRaisesRegex(fretbem.InputError, "grid.n"):
            fretbem.Scenario.from_dict({"material": {"E": 1e9, "nu": 0.3},
                                        "grid": {"n": 32.5, "length": 1e-3}})

    def test_errors_name_their_source(self):
        with self.assertRaisesRegex(fretbem.InputError, "^Scenario.from_dict: material.nu"):
            fretbem.Scenario.from_dict({"material": {"E": 1e9, "nu": 0.7},
                                        "grid": {"n": 16, "length": 1e-3}})
        with self.assertRaisesRegex(fretbem.InputError, "^Scenario.from_text: "):
            fretbem.Scenario.from_text("[material]\nE = 1e9\nnu = 0.7\n")
        path = os.path.join(tempfile.mkdtemp(prefix="fretbem_py_"), "bad.ini")
        with open(path, "w") as f:
            f.write("[material]\nE = 1e9\nnu = 0.7\n")
        with self.assertRaisesRegex(fretbem.InputError, "bad.ini"):
            fretbem.Scenario.from_file(path)

    def test_contact_values_are_properties(self):
        c = fretbem.Contact((210e9, 0.3), mu=0.5, radius=0.01, normal_force=10)
        E_star = 210e9 / (1 - 0.3 ** 2)
        a = (3 * 10 * 0.01 / (4 * E_star)) ** (1 / 3)  # Johnson eq. 4.22
        self.assertAlmostEqual(c.contact_radius / a, 1.0, places=12)
        self.assertAlmostEqual(c.indentation / (a * a / 0.01), 1.0, places=12)
        self.assertAlmostEqual(c.peak_pressure / (3 * 10 / (2 * math.pi * a * a)), 1.0, places=12)
        self.assertEqual(c.hertz_radius(), c.contact_radius)  # the method stays for scripts
        with self.assertRaisesRegex(ValueError, "radius and normal_force"):
            fretbem.Contact((210e9, 0.3)).contact_radius

    def test_displacement_energy_meets_the_gross_slip_line(self):
        # At D = u* the Mindlin–Deresiewicz energy at full sliding, 0.6 mu^2 P^2/(a G*), equals
        # the gross-slip line 4 mu P (u* - 4u*/5), u* = 3 mu P/(4 a G*) (Johnson §7.5).
        c = fretbem.Contact((210e9, 0.3), mu=0.5, radius=0.01, normal_force=10)
        us = c.sliding_shift(c.indentation)
        muP = 0.5 * 10
        self.assertAlmostEqual(us / (3 * muP / (4 * c.contact_radius * c.G_star)), 1.0, places=12)
        full = 0.6 * muP ** 2 / (c.contact_radius * c.G_star)
        self.assertAlmostEqual(float(c.displacement_energy(us * (1 - 1e-12))) / full, 1.0, places=6)
        self.assertAlmostEqual(float(c.displacement_energy(us)) / full, 1.0, places=12)
        self.assertAlmostEqual(float(c.displacement_energy(3 * us)) / (4 * muP * 2.2 * us), 1.0,
                               places=12)

    def test_two_steppers_on_one_model_count_their_own(self):
        sc = fretbem.Scenario.from_file(SCENARIO, SMALL)
        model = fretbem.Model(sc)
        a, b = fretbem.Stepper(model), fretbem.Stepper(model)
        rows_a, rows_b = [], []
        for _ in range(model.steps):
            rows_a.append(a.advance())
            rows_b.append(b.advance())
        self.assertEqual(a.convolutions, sum(r["convolutions"] for r in rows_a))
        self.assertEqual(b.convolutions, sum(r["convolutions"] for r in rows_b))
        alone = list(fretbem.Stepper(fretbem.Model(sc)))
        for ra, rb, r in zip(rows_a, rows_b, alone):
            for key in ("Fx", "Ux", "dissipation", "stick_area"):
                self.assertEqual(ra[key], r[key], key)
                self.assertEqual(rb[key], r[key], key)

    def test_hostile_arguments_raise_and_never_crash(self):
        """Arguments found by tools/bench/hostile_hunt.py must raise, never crash or give NaN:
        Stepper(None) (a SIGSEGV of the interpreter unchecked), a surface of 1e200 m and NaN
        written into the surface view ("residual -nan"), GW stiffness past full sliding (NaN),
        Contact(radius=-1) (complex)."""
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
