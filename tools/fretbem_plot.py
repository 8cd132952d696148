"""What every fretbem plot tool shares: reading a run's outputs, the closed forms users compare
against, and one figure style saved as PNG and PDF.

Imported by tools/plot_*.py (they run with Debian's /usr/bin/python3, python3-numpy, -h5py,
-matplotlib). Units are SI unless a name says otherwise.
"""
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

# Readable at publication size: a single-column figure is ~3.3 in wide, so 9-10 pt text.
STYLE = {
    "font.size": 9,
    "axes.labelsize": 9,
    "axes.titlesize": 9,
    "legend.fontsize": 8,
    "xtick.labelsize": 8,
    "ytick.labelsize": 8,
    "axes.grid": True,
    "grid.alpha": 0.3,
    "savefig.dpi": 200,
    "savefig.bbox": "tight",
    "pdf.fonttype": 42,  # embed TrueType: editable text in journals' pipelines
}


def fail(tool, message):
    sys.exit(f"{tool}: {message}")


def figure(ncols=1, nrows=1, width=3.4, height=2.8, **kw):
    """A figure of ncols x nrows panels, each width x height inches, in the shared style."""
    plt.rcParams.update(STYLE)
    return plt.subplots(nrows, ncols, figsize=(width * ncols, height * nrows), squeeze=False,
                        layout="constrained", **kw)


def save(fig, out):
    """Saves the figure as OUT (PNG) and beside it as PDF; prints both paths."""
    root, ext = os.path.splitext(out)
    png = out if ext.lower() == ".png" else root + ".png"
    pdf = root + ".pdf"
    fig.savefig(png)
    fig.savefig(pdf)
    plt.close(fig)
    print(png)
    print(pdf)


def read_csv(path, tool):
    """A fretbem CSV (header row, numbers, `nan` allowed; `#` comment lines skipped) as a dict
    of numpy columns."""
    if not os.path.exists(path):
        fail(tool, f"{path}: not found")
    with open(path) as f:
        lines = [ln for ln in f if ln.strip() and not ln.lstrip().startswith("#")]
    if not lines:
        fail(tool, f"{path}: empty")
    names = [c.strip() for c in lines[0].split(",")]
    rows = [[float(c) if c.strip() else math.nan for c in ln.split(",")] for ln in lines[1:]]
    data = np.array(rows, dtype=float).reshape(len(rows), len(names))
    return {n: data[:, i] for i, n in enumerate(names)}


def read_scenario(run_dir):
    """The resolved scenario of a run as {'section.key': 'value'}: from result.h5 when h5py
    can read it, else from the run's INI copy if present; {} when neither exists."""
    text = None
    h5 = os.path.join(run_dir, "result.h5")
    if os.path.exists(h5):
        try:
            import h5py

            with h5py.File(h5, "r") as f:
                t = f["scenario"][()]
                text = t.decode() if isinstance(t, bytes) else str(t)
        except (ImportError, OSError, KeyError):
            text = None
    if text is None:
        return {}
    out, section = {}, None
    for line in text.splitlines():
        line = line.split("#")[0].strip()
        if line.startswith("["):
            section = line.strip("[] ")
        elif "=" in line and section:
            k, v = (s.strip() for s in line.split("=", 1))
            out[f"{section}.{k}"] = v
    return out


def number(scn, key, default=None):
    v = scn.get(key)
    try:
        return float(v) if v is not None else default
    except ValueError:
        return default


class Contact:
    """Effective moduli (DESIGN §1) and, for spheres under a constant normal force, Hertz and
    Mindlin–Deresiewicz (Johnson, Contact Mechanics, §§4.2, 7.2, 7.5)."""

    def __init__(self, scn):
        E1, n1 = number(scn, "material.E"), number(scn, "material.nu")
        E2, n2 = number(scn, "material.E2"), number(scn, "material.nu2")
        self.mu = number(scn, "material.mu", 0.3)
        inv_e = (1 - n1**2) / E1
        inv_g = (2 - n1) / (4 * E1 / (2 * (1 + n1)))
        if E2 is not None and n2 is not None:
            inv_e += (1 - n2**2) / E2
            inv_g += (2 - n2) / (4 * E2 / (2 * (1 + n2)))
        self.E_star, self.G_star = 1 / inv_e, 1 / inv_g
        self.sphere = scn.get("surface.type") == "sphere"
        self.R = number(scn, "surface.radius")
        self.P = number(scn, "load.normal_force")

    @property
    def hertz_ok(self):
        return self.sphere and self.R is not None and self.P is not None

    def hertz_radius(self):
        return (3 * self.P * self.R / (4 * self.E_star)) ** (1 / 3)

    def sliding_shift(self, delta):
        """Full-sliding shift U* = mu delta E*/G* (delta: normal approach)."""
        return self.mu * delta * self.E_star / self.G_star

    def md_shift(self, Q):
        """Monotone Cattaneo–Mindlin shift under tangential force Q (|Q| < mu P):
        (3 mu P / 4 a G*) (1 - (1 - Q/mu P)^(2/3)), odd in Q."""
        a, muP = self.hertz_radius(), self.mu * self.P
        Q = np.asarray(Q, dtype=float)
        return np.sign(Q) * 3 * muP / (4 * a * self.G_star) * (1 - (1 - np.abs(Q) / muP) ** (2 / 3))

    def md_loop(self, Q_star, points=200):
        """Steady Mindlin–Deresiewicz loop between -Q* and +Q* (Masing: branches are the
        monotone curve doubled in size): (U, F) along unloading then reloading."""
        Q = np.linspace(Q_star, -Q_star, points)
        down = self.md_shift(Q_star) - 2 * self.md_shift((Q_star - Q) / 2)
        # Reloading is unloading mirrored through the origin: U_up(-F) = -U_down(F).
        return np.concatenate((down, -down)), np.concatenate((Q, -Q))

    def md_energy(self, Q_star):
        """Energy per cycle (J): (9 mu^2 P^2 / 10 a)(4/G*)[1 - (1-x)^(5/3) - (5x/6)(1 + (1-x)^(2/3))],
        x = Q*/mu P (Johnson eq. 7.60 with (2-nu1)/G1 + (2-nu2)/G2 = 4/G*)."""
        a, muP = self.hertz_radius(), self.mu * self.P
        x = Q_star / muP
        bracket = 1 - (1 - x) ** (5 / 3) - 5 * x / 6 * (1 + (1 - x) ** (2 / 3))
        return 9 * muP**2 / (10 * a) * 4 / self.G_star * bracket


def cycle_of_steps(time):
    """Cycle index of each step: a step belongs to the cycle holding (t_{k-1}, t_k]
    (row 0, t = 0, to cycle 0)."""
    return np.maximum(np.ceil(np.asarray(time) - 1e-12) - 1, 0).astype(int)
