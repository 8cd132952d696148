#!/usr/bin/python3
"""The paper's eq. 25, k_x/k_x0 = (1 - F_x/(mu F_z))^(1/(1+H)), against the contact fraction:
the exponent alpha fitted per member of a fretbem sweep over surface.hurst and load.normal_force
(and optionally surface.seed) of a monotone rough-surface ramp (rough_monotone.ini).

usage: tools/plot_fig3_contact_fraction.py STUDY_DIR [--out fig3_contact_fraction.png]

Per member: f = F_x/(mu F_z) and k_x/k_x0 (k_x0: row 0) from its timeseries.csv, rows where f
still rises; alpha is the least-squares slope of log(k_x/k_x0) against log(1 - f) through the
origin over f <= 0.9 (as docs/paper-reproduction.md); the contact fraction is the row-0
contact area over the domain area. Prints one line per member and plots alpha against the
contact fraction per H (mean and standard deviation over seeds when surface.seed is varied),
with eq. 25's 1/(1+H) as dashed lines; next to it, alpha against the normal stiffness exponent
beta (k_z ~ F_z^beta, eq. 21) measured on the same surfaces from k_x0 = (G*/E*) k_z (eq. 22) at
neighbouring normal forces: eq. 23 says alpha = beta. Writes PNG and PDF.
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
    """alpha, contact fraction, k_x0 and k_x/k_x0 at f = 0.5 of one member."""
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
    k_half = float(np.interp(0.5, f, k)) if f[-1] >= 0.5 else np.nan
    return alpha, contact, float(kx[0]), k_half


def normal_exponents(members):
    """Normal stiffness exponent beta in k_z ~ F_z^beta (paper eq. 21) per (H, seed), between
    neighbouring normal forces, from k_x0 = (G*/E*) k_z (eq. 22): {(H, seed, F_hi): beta}."""
    by = {}
    for m in members:
        by.setdefault((m["H"], m["seed"]), []).append((m["Fz"], m["kx0"]))
    out = {}
    for (H, seed), pts in by.items():
        pts.sort()
        for (f1, k1), (f2, k2) in zip(pts, pts[1:]):
            out[(H, seed, f2)] = np.log(k2 / k1) / np.log(f2 / f1)
    return out


def mean_sd(v):
    v = np.array([x for x in v if np.isfinite(x)])
    if not len(v):
        return np.nan, np.nan, 0
    return v.mean(), (v.std(ddof=1) if len(v) > 1 else np.nan), len(v)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("study_dir")
    ap.add_argument("--out", default=None)
    args = ap.parse_args()
    rows = finished_rows(args.study_dir, TOOL)
    members = []
    print("H, seed, F_z (N), contact fraction (%), fitted alpha, k_x/k_x0 at f = 0.5, 1/(1+H)")
    for r in rows:
        d = os.path.join(args.study_dir, r["dir"])
        mu, length, H = scenario_values(d)
        alpha, contact, kx0, k_half = fitted_alpha(d, mu, length)
        scn = fp.read_scenario(d)
        m = dict(H=H, seed=scn.get("surface.seed", ""), Fz=fp.number(scn, "load.normal_force"),
                 alpha=alpha, contact=contact, kx0=kx0, k_half=k_half)
        members.append(m)
        print(f"{H:g}, {m['seed']}, {m['Fz']:g}, {100 * contact:.3f}, {alpha:.3f}, "
              f"{k_half:.3f}, {1 / (1 + H):.3f}")
    beta = normal_exponents(members)
    # Per (H, F_z): mean and standard deviation over seeds.
    groups = {}
    for m in members:
        groups.setdefault((m["H"], m["Fz"]), []).append(m)
    print("\nper H and F_z over seeds: H, F_z (N), seeds, contact (%), alpha mean, alpha sd, "
          "k_x/k_x0(0.5) mean, eq. 25 at 0.5, beta_normal below F_z mean, beta sd, 1/(1+H)")
    table = []
    for (H, Fz), ms in sorted(groups.items()):
        a, a_sd, n = mean_sd([m["alpha"] for m in ms])
        kh, _, _ = mean_sd([m["k_half"] for m in ms])
        c, _, _ = mean_sd([m["contact"] for m in ms])
        b, b_sd, _ = mean_sd([beta.get((H, m["seed"], Fz), np.nan) for m in ms])
        table.append((H, Fz, n, c, a, a_sd, b, b_sd))
        print(f"{H:g}, {Fz:g}, {n}, {100 * c:.3f}, {a:.3f}, {a_sd:.3f}, {kh:.3f}, "
              f"{0.5 ** (1 / (1 + H)):.3f}, {b:.3f}, {b_sd:.3f}, {1 / (1 + H):.3f}")
    fig, axs = fp.figure(ncols=2, width=4.2, height=3.2)
    ax = axs[0, 0]
    for i, H in enumerate(sorted({t[0] for t in table})):
        t = [x for x in table if x[0] == H]
        c = np.array([x[3] for x in t]) * 100
        a = np.array([x[4] for x in t])
        err = np.nan_to_num(np.array([x[5] for x in t]))
        ax.errorbar(c, a, yerr=err, fmt="o-", color=f"C{i}", capsize=2, label=f"H = {H:g}")
        ax.axhline(1 / (1 + H), color=f"C{i}", ls="--", lw=0.8)
    ax.set_xscale("log")
    ax.set_xlabel("contact fraction A/L² (%)")
    ax.set_ylabel("fitted α in k_x/k_x0 = (1 − F_x/μF_z)^α")
    ax.set_title("eq. 25 (dashed: 1/(1+H)); bars: sd over seeds")
    ax.legend()
    ax = axs[0, 1]
    for i, H in enumerate(sorted({t[0] for t in table})):
        t = [x for x in table if x[0] == H and np.isfinite(x[6])]
        if t:
            ax.errorbar([x[6] for x in t], [x[4] for x in t],
                        xerr=np.nan_to_num([x[7] for x in t]),
                        yerr=np.nan_to_num([x[5] for x in t]), fmt="o", color=f"C{i}",
                        capsize=2, label=f"H = {H:g}")
    ax.plot([0, 1.1], [0, 1.1], "k:", lw=1, label="α = β (eq. 23)")
    ax.set_xlabel("normal stiffness exponent β (k_z ∝ F_z^β, below F_z)")
    ax.set_ylabel("tangential α")
    ax.set_title("α against the measured normal exponent")
    ax.legend(fontsize=7)
    fp.save(fig, args.out or os.path.join(args.study_dir, "fig3_contact_fraction.png"))


if __name__ == "__main__":
    fp.guarded(main, TOOL)
