#!/usr/bin/python3
"""The paper's eq. 25, k_x/k_x0 = (1 - F_x/(mu F_z))^(1/(1+H)), against the contact fraction:
the exponent alpha fitted per member of a fretbem sweep over surface.hurst and load.normal_force
(and optionally surface.seed) of a monotone rough-surface ramp (rough_monotone.ini).

usage: tools/plot_fig3_contact_fraction.py STUDY_DIR [--out fig3_contact_fraction.png]

Per member: f = F_x/(mu F_z) and k_x/k_x0 (k_x0: row 0) from its timeseries.csv, rows where f
still rises; alpha is the least-squares slope of log(k_x/k_x0) against log(1 - f) through the
origin over f <= 0.9 (as docs/paper-reproduction.md); the contact fraction is the row-0
contact area over the domain area. Prints one line per member and plots alpha against the
contact fraction per H, with eq. 25's 1/(1+H) as dashed lines. Writes PNG and PDF.
"""
import argparse
import csv
import os

import numpy as np
import fretbem_plot as fp
from sweep_results import finished_rows

TOOL = "plot_fig3_contact_fraction"


def scenario_values(member_dir):
    scn = fp.read_scenario(member_dir)
    return fp.number(scn, "material.mu"), fp.number(scn, "grid.length"), fp.number(scn, "surface.hurst")


def fitted_alpha(member_dir, mu, length):
    with open(os.path.join(member_dir, "timeseries.csv")) as f:
        rows = list(csv.DictReader(f))
    fz = np.array([float(r["Fz"]) for r in rows])
    f = np.array([float(r["Fx"]) for r in rows]) / (mu * fz)
    kx = np.array([float(r["kx"]) for r in rows])
    keep = [0]
    for i in range(1, len(f)):
        if f[i] > f[keep[-1]]:
            keep.append(i)
    f, k = f[keep], kx[keep] / kx[0]
    use = (f > 0) & (f <= 0.9) & (k > 0)
    x, y = np.log(1 - f[use]), np.log(k[use])
    alpha = float(np.dot(x, y) / np.dot(x, x))
    contact = float(rows[0]["contact_area"]) / length**2
    return alpha, contact


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("study_dir")
    ap.add_argument("--out", default=None)
    args = ap.parse_args()
    rows = finished_rows(args.study_dir, TOOL)
    by_h = {}
    print("H, F_z (N), contact fraction (%), fitted alpha, 1/(1+H)")
    for r in rows:
        d = os.path.join(args.study_dir, r["dir"])
        mu, length, H = scenario_values(d)
        alpha, contact = fitted_alpha(d, mu, length)
        by_h.setdefault(H, []).append((contact, alpha))
        print(f"{H:g}, {r.get('load.normal_force', '')}, {100 * contact:.3f}, {alpha:.3f}, "
              f"{1 / (1 + H):.3f}")
    fig, axs = fp.figure(width=4.2, height=3.2)
    ax = axs[0, 0]
    for i, H in enumerate(sorted(by_h)):
        pts = sorted(by_h[H])
        c = np.array([p[0] for p in pts]) * 100
        a = np.array([p[1] for p in pts])
        ax.semilogx(c, a, "o-", color=f"C{i}", label=f"H = {H:g}")
        ax.axhline(1 / (1 + H), color=f"C{i}", ls="--", lw=0.8)
    ax.set_xlabel("contact fraction A/L² (%)")
    ax.set_ylabel("fitted α in k_x/k_x0 = (1 − F_x/μF_z)^α")
    ax.set_title("eq. 25 (dashed: 1/(1+H)) against contact fraction")
    ax.legend()
    fp.save(fig, args.out or os.path.join(args.study_dir, "fig3_contact_fraction.png"))


if __name__ == "__main__":
    main()
