#!/usr/bin/python3
"""Stick area, tangential stiffness and stick force against the tangential load of one run (or
several overlaid): the paper's Figs. 2-4 for a single surface, without an ensemble.

usage: tools/plot_monotone.py RUN_DIR [RUN_DIR ...] [--labels A,B] [--out FILE.png]

Reads RUN_DIR/timeseries.csv (the rows where F_x/(mu F_z) still rises: the first loading of any
path) and the scenario in result.h5. Panels: A_stick/A_0, k_x/k_x,0 and F_stick/(mu F_z)
against F_x/(mu F_z). References: for a sphere Cattaneo–Mindlin (Johnson §7.2, c/a =
(1 - f)^(1/3): A_stick/A_0 = (1 - f)^(2/3), k_x/k_x,0 = c/a, F_stick/(mu F_z) = 1 - (1 - (c/a)^2)^(3/2)
- (c/a)^3); for a rough surface the paper's eq. 15 (1 - f), eq. 25 (1 - f)^(1/(1 + H)) and the
GW stick force (eqs. 27 + 14). k_x needs solver.stiffness = every (the default). Writes FILE.png
and FILE.pdf (default: monotone.png in the first run's folder).
"""
import argparse
import os

import numpy as np

import fretbem_plot as fp
from plot_paper_figures import gw_stick_force, read_member

TOOL = "plot_monotone"


def sphere_references(ax_a, ax_k, ax_s):
    f = np.linspace(0, 1, 200)
    c = (1 - f) ** (1 / 3)  # Cattaneo: stick radius over contact radius
    ax_a.plot(f, c ** 2, "k--", lw=0.8, label="Cattaneo–Mindlin")
    ax_k.plot(f, c, "k--", lw=0.8, label="Cattaneo–Mindlin")
    ax_s.plot(f, 1 - (1 - c ** 2) ** 1.5 - c ** 3, "k--", lw=0.8, label="Cattaneo–Mindlin")


def rough_references(ax_a, ax_k, ax_s, hurst):
    f = np.linspace(0, 1, 200)
    ax_a.plot(f, 1 - f, "k--", lw=0.8, label="eq. 15")
    ax_k.plot(f, 1 - f, "k--", lw=0.8, label="eq. 26 (GW)")
    if hurst:
        ax_k.plot(f, (1 - f) ** (1 / (1 + hurst)), "k:", lw=0.8, label=f"eq. 25, H = {hurst:g}")
    fg, fs = gw_stick_force(np.linspace(0, 12, 400))
    ax_s.plot(fg, fs, "k--", lw=0.8, label="GW eqs. 27 + 14")


def member(run_dir):
    """The run's first-loading rows in the paper's normalisation, and its scenario."""
    path = os.path.join(run_dir, "timeseries.csv")
    ts = fp.read_csv(path, TOOL)  # one line when missing or torn
    scn = fp.read_scenario(run_dir)
    mu = fp.number(scn, "material.mu", 0.3)
    m = read_member(path, mu)
    if len(m["f"]) < 2:
        fp.fail(TOOL, f"{path}: F_x never rises: no tangential loading to plot")
    if not np.any(np.isfinite(ts["kx"])) or not np.isfinite(m["kx"][0]):
        m["kx"] = np.full_like(m["f"], np.nan)
    return m, scn


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("run_dirs", nargs="+", metavar="RUN_DIR")
    ap.add_argument("--labels", default=None, help="legend labels of the runs, comma separated")
    ap.add_argument("--out", default=None, help="image file (PNG; a PDF is written beside it)")
    args = ap.parse_args()
    labels = fp.run_labels(args, TOOL)
    fig, axes = fp.figure(ncols=3, width=3.0, height=3.0)
    ax_a, ax_k, ax_s = axes[0]
    kinds = set()
    for k, (d, lab) in enumerate(zip(args.run_dirs, labels)):
        m, scn = member(d)
        ax_a.plot(m["f"], m["stick"], "o-", ms=2, lw=1, color=f"C{k}", label=lab)
        ax_k.plot(m["f"], m["kx"], "o-", ms=2, lw=1, color=f"C{k}", label=lab)
        ax_s.plot(m["f"], m["fstick"], "o-", ms=2, lw=1, color=f"C{k}", label=lab)
        kind = scn.get("surface.type", "")
        if kind not in kinds:
            kinds.add(kind)
            if kind == "sphere":
                sphere_references(ax_a, ax_k, ax_s)
            else:
                rough_references(ax_a, ax_k, ax_s, fp.number(scn, "surface.hurst"))
    for ax, y in ((ax_a, r"$A_{stick}/A_0$"), (ax_k, r"$k_x/k_{x,0}$"),
                  (ax_s, r"$F_{stick}/\mu F_z$")):
        ax.set(xlabel=r"$F_x/\mu F_z$", ylabel=y, xlim=(0, 1), ylim=(0, None))
    ax_a.legend(frameon=False, fontsize=7)
    ax_k.legend(frameon=False, fontsize=7)
    out = args.out or os.path.join(args.run_dirs[0], "monotone.png")
    fp.save(fig, out)


if __name__ == "__main__":
    fp.guarded(main, TOOL)
