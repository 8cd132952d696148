#!/usr/bin/python3
"""A Mindlin fretting loop driven from Python, against the Mindlin–Deresiewicz closed form.

    PYTHONPATH=build/python python/examples/mindlin_loop.py [N] [OUT.png]
"""
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import fretbem  # noqa: E402

n = sys.argv[1] if len(sys.argv) > 1 else "128"
out = sys.argv[2] if len(sys.argv) > 2 else "mindlin_loop.png"
root = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
sc = fretbem.Scenario.from_file(os.path.join(root, "scenarios", "mindlin_cycle.ini"),
                                [f"grid.n={n}"])
stepper = fretbem.Stepper(fretbem.Model(sc))
rows = list(stepper)                                   # one dict per step
t = np.array([r["time"] for r in rows])
Fx = np.array([r["Fx"] for r in rows])
Ux = np.array([r["Ux"] for r in rows])

# Energy of the last cycle (t in (2, 3]: cycles.csv's last row) against Mindlin–Deresiewicz.
Fz = rows[0]["Fz"]
contact = fretbem.Contact((210e9, 0.3), mu=sc.mu, radius=0.01, normal_force=Fz)
Q_star = 0.6 * sc.mu * Fz
start = np.searchsorted(t, 2 - 1e-12)    # the step at t = 2 closes cycle 2 and opens cycle 3
last = np.arange(len(t)) >= start
energy = stepper.cycles[-1]["dissipated_energy"]
md = contact.md_energy(Q_star)
print(f"energy per cycle {energy:.5g} J, Mindlin–Deresiewicz {md:.5g} J "
      f"({100 * (energy / md - 1):+.2f} %)")

u, f = contact.md_loop(Q_star)
fig, ax = plt.subplots(figsize=(4, 3.2), layout="constrained")
ax.plot(Ux[last] * 1e9, Fx[last], label="fretbem (cycle 3)")
ax.plot(u * 1e9, f, "k--", lw=0.8, label="Mindlin–Deresiewicz")
ax.set(xlabel="$U_x$ (nm)", ylabel="$F_x$ (N)")
ax.legend(frameon=False)
fig.savefig(out, dpi=150)
print(out)
