#!/usr/bin/python3
"""The paper's Figs. 2-4 from a `fretbem ensemble` output directory, a Fig. 5-style stick/slip
map sequence from one run's result.h5, and a summary of the measured numbers.

    tools/plot_paper_figures.py ENSEMBLE_DIR [--fig5 RUN_DIR] [--out FIGDIR]

Reads ENSEMBLE_DIR/aggregate.csv (means and 95 % Student-t half widths per H and bin of
F_x/(mu F_z); each member's curve was interpolated to the bin centres) and the members' time
series for the per-member statistics. Analytic curves: eq. 15 (Fig. 2), eq. 25 per H and
eq. 26 (Fig. 3), eq. 27 with eq. 14 (Fig. 4, GW).
"""
import argparse
import csv
import glob
import math
import os

import numpy as np
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import fretbem_plot as fp  # noqa: E402

TOOL = "plot_paper_figures"


def read_aggregate(path):
    if not os.path.exists(path):
        fp.fail(TOOL, f"{path}: not found (run fretbem ensemble first)")
    with open(path) as f:
        rows = list(csv.DictReader(f))
    if not rows:
        fp.fail(TOOL, f"{path}: no rows")
    out = {}
    for r in rows:
        # An empty cell is a value the bin has not got (no member, or one: no interval).
        out.setdefault(float(r["hurst"]), []).append(
            {k: float(v) if v != "" else np.nan for k, v in r.items()})
    return {H: {k: np.array([r[k] for r in rs]) for k in rs[0]} for H, rs in out.items()}


def read_member(path, mu):
    """Member curve in the paper's normalisation, rows where F_x still rises (as the C++ does)."""
    d = np.genfromtxt(path, delimiter=",", names=True)
    f = d["Fx"] / (mu * d["Fz"])
    keep = [0]
    for i in range(1, len(f)):
        if f[i] > f[keep[-1]]:
            keep.append(i)
    k = np.array(keep)
    return dict(f=f[k], stick=d["stick_area"][k] / d["contact_area"][0],
                kx=d["kx"][k] / d["kx"][0], fstick=d["Fx_stick"][k] / (mu * d["Fz"][k]),
                d=d)


def t975(n):
    try:
        from scipy.stats import t
        return float(t.ppf(0.975, n - 1))
    except ImportError:  # normal approximation
        return 1.96


def gw_stick_force(b):
    """Eq. 27 and eq. 14, parametric in b = d_min/lambda."""
    erfc = np.vectorize(math.erfc)
    fs = np.exp(-b) * (2 * np.sqrt(b / np.pi) - 1) + erfc(np.sqrt(b))
    return 1 - np.exp(-b), fs


def errorplot(ax, agg, key, label_fmt="H = {:g}"):
    for H, a in sorted(agg.items()):
        ax.errorbar(a["f_centre"], a[key + "_mean"], yerr=a[key + "_ci95"], fmt="o-", ms=3,
                    capsize=2, lw=1, label=label_fmt.format(H))


def fig2(agg, out):
    fig, ax = plt.subplots(figsize=(5, 4))
    errorplot(ax, agg, "stick_area")
    x = np.linspace(0, 1, 50)
    ax.plot(x, 1 - x, "k--", label="eq. 15")
    ax.set(xlabel=r"$F_x/\mu F_z$", ylabel=r"$A_{stick}/A_0$", xlim=(0, 1), ylim=(0, 1.02))
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "fig2_stick_area.png"), dpi=80)


def fig3(agg, out):
    fig, ax = plt.subplots(figsize=(5, 4))
    errorplot(ax, agg, "kx")
    x = np.linspace(0, 1, 200)
    for i, H in enumerate(sorted(agg)):
        ax.plot(x, (1 - x) ** (1 / (1 + H)), ":", color=f"C{i}", lw=1)
    ax.plot(x, 1 - x, "k--", label="eq. 26 (GW)")
    ax.plot([], [], "k:", label="eq. 25 per H")
    ax.set(xlabel=r"$F_x/\mu F_z$", ylabel=r"$k_x/k_{x,0}$", xlim=(0, 1), ylim=(0, 1.02))
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "fig3_stiffness.png"), dpi=80)


def fig4(agg, out):
    fig, ax = plt.subplots(figsize=(5, 4))
    errorplot(ax, agg, "Fx_stick")
    f, fs = gw_stick_force(np.linspace(0, 12, 400))
    ax.plot(f, fs, "g-", lw=2, label="GW eqs. 27 + 14")
    ax.set(xlabel=r"$F_x/\mu F_z$", ylabel=r"$F_{stick}/\mu F_z$", xlim=(0, 1), ylim=(0, None))
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "fig4_stick_force.png"), dpi=80)


def fig5(run_dir, mu, out, panels=5):
    import h5py
    d = np.genfromtxt(os.path.join(run_dir, "timeseries.csv"), delimiter=",", names=True)
    with h5py.File(os.path.join(run_dir, "result.h5"), "r") as h5:
        steps = sorted(h5["fields"].keys())
        f = [d["Fx"][int(s[5:])] / (mu * d["Fz"][int(s[5:])]) for s in steps]
        # Panels from no load to (nearly) full sliding, one per distinct state.
        sel = [i for i in range(len(steps)) if i == 0 or f[i] - f[i - 1] > 1e-9][:panels]
        fig, axs = plt.subplots(1, len(sel), figsize=(2.2 * len(sel), 2.5))
        cmap = matplotlib.colors.ListedColormap(["white", "black", "0.6"])  # open, stick, slip
        for ax, i in zip(np.atleast_1d(axs), sel):
            st = np.array(h5["fields"][steps[i]]["state"])  # array[j, i]: rows along y
            ax.imshow(st, cmap=cmap, vmin=0, vmax=2, origin="lower", interpolation="nearest")
            ax.set_title(rf"$F_x/\mu F_z$ = {f[i]:.2f}", fontsize=8)
            ax.set_xticks([]), ax.set_yticks([])
    fig.tight_layout()
    fig.savefig(os.path.join(out, "fig5_stick_slip_maps.png"), dpi=80)


def summary(ens, agg, mu):
    """Per H: deviation of A_stick/A0 from eq. 15, stiffness exponent fit, stick-force peak."""
    lines = ["H  members  A_dev_bins  A_dev_members  alpha_fit  1/(1+H)  rms_eq25  rms_eq26"
             "  Fs_peak_f(mean+-ci)  Fs_peak_value"]
    for H, a in sorted(agg.items()):
        f = a["f_centre"]
        dev_bins = np.nanmean(np.abs(a["stick_area_mean"] - (1 - f)))
        ms = [read_member(p, mu) for p in sorted(glob.glob(
            os.path.join(ens, f"H{H:g}", "seed_*", "timeseries.csv")))]
        dev_m = np.mean([np.mean(np.abs(m["stick"] - (1 - m["f"]))) for m in ms])
        ok = np.isfinite(a["kx_mean"]) & (f <= 0.9)
        # k = (1 - f)^alpha: least squares through the origin in log-log.
        lx, ly = np.log(1 - f[ok]), np.log(a["kx_mean"][ok])
        alpha = float(np.sum(lx * ly) / np.sum(lx * lx))
        r25 = np.sqrt(np.nanmean((a["kx_mean"][ok] - (1 - f[ok]) ** (1 / (1 + H))) ** 2))
        r26 = np.sqrt(np.nanmean((a["kx_mean"][ok] - (1 - f[ok])) ** 2))
        peaks = np.array([m["f"][np.argmax(m["fstick"])] for m in ms])
        ci = t975(len(peaks)) * peaks.std(ddof=1) / np.sqrt(len(peaks)) if len(peaks) > 1 else np.nan
        lines.append(f"{H:g}  {len(ms)}  {dev_bins:.4f}  {dev_m:.4f}  {alpha:.3f}  "
                     f"{1 / (1 + H):.3f}  {r25:.3f}  {r26:.3f}  {peaks.mean():.3f}+-{ci:.3f}  "
                     f"{np.nanmax(a['Fx_stick_mean']):.3f}")
    fgw, fsgw = gw_stick_force(np.linspace(0, 12, 20001))
    lines.append(f"GW eq. 27: peak F_stick/muF_z = {fsgw.max():.4f} at F_x/muF_z = "
                 f"{fgw[np.argmax(fsgw)]:.4f}")
    return "\n".join(lines)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("ensemble")
    ap.add_argument("--fig5", help="run directory with result.h5 holding 'state' fields")
    ap.add_argument("--mu", type=float, default=0.5, help="friction coefficient (default 0.5)")
    ap.add_argument("--out", default=".", help="figure directory")
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    agg = read_aggregate(os.path.join(a.ensemble, "aggregate.csv"))
    fig2(agg, a.out)
    fig3(agg, a.out)
    fig4(agg, a.out)
    if a.fig5:
        fig5(a.fig5, a.mu, a.out)
    text = summary(a.ensemble, agg, a.mu)
    print(text)
    open(os.path.join(a.out, "summary.txt"), "w").write(text + "\n")


if __name__ == "__main__":
    fp.guarded(main, TOOL)
