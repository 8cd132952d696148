#!/usr/bin/python3
"""Energy dissipated per steady cycle against the tangential amplitude Q*/(mu P), log-log, from a
fretbem sweep over load.amplitude (sweep.csv): a sphere next to Mindlin-Deresiewicz, or rough
surfaces (one curve per value of the other varied keys, mean over surface.seed with the
seeds' range as a band, a slope-3 guide).

usage: tools/plot_energy_per_cycle.py STUDY_DIR [--out energy_per_cycle.png]

Closed form (fretbem_plot.Contact.md_energy, Johnson eq. 7.60): W(q) = (24/5) mu P u*
[1 - (1-q)^(5/3) - (5q/6)(1 + (1-q)^(2/3))] ~ (4/27) mu P u* q^3, u* = mu delta E*/G*. The slip
annulus is a (1 - (1-q)^(1/3)) wide: the grid resolves it with at least two cells only where
that exceeds 2h; points below are drawn hollow. Prints one line per member (sphere) or per
group and amplitude (rough). Writes PNG and PDF.
"""
import argparse
import os

import numpy as np
import fretbem_plot as fp
from sweep_results import finished_rows

TOOL = "plot_energy_per_cycle"


def plot_sphere(rows, scn, out):
    c = fp.Contact(scn)
    muP, a = c.mu * c.P, c.hertz_radius()
    ustar = c.sliding_shift(a * a / c.R)
    h = fp.number(scn, "grid.length") / fp.number(scn, "grid.n")
    q = np.array([float(r["load.amplitude"]) for r in rows])
    W = np.array([float(r["dissipated_energy"]) for r in rows])
    ring = a * (1 - (1 - q) ** (1 / 3)) / h
    Wmd = c.md_energy(q * muP)
    print("q, W (J), W Mindlin-Deresiewicz (J), ratio, slip annulus (cells)")
    for i in np.argsort(q):
        print(f"{q[i]:.4g}, {W[i]:.6g}, {Wmd[i]:.6g}, {W[i] / Wmd[i]:.4f}, {ring[i]:.2f}")
    fig, axs = fp.figure(width=4.2, height=3.2)
    ax = axs[0, 0]
    qq = np.logspace(np.log10(min(q.min(), 0.01)), np.log10(0.999), 200)
    ax.loglog(qq, c.md_energy(qq * muP) / (muP * ustar), "k-", lw=1, label="Mindlin–Deresiewicz")
    ax.loglog(qq, 4 / 27 * qq**3, "k:", lw=1, label="slope 3: (4/27) q³")
    ok = ring >= 2
    ax.loglog(q[ok], W[ok] / (muP * ustar), "o", color="C0", label="fretbem (annulus ≥ 2 cells)")
    ax.loglog(q[~ok], W[~ok] / (muP * ustar), "o", mfc="none", color="C0",
              label="fretbem (annulus < 2 cells)")
    ax.set_xlabel("Q*/(μP)")
    ax.set_ylabel("W / (μP u*)")
    ax.set_title(f"energy per cycle, sphere, a/h = {a / h:.0f}")
    ax.legend()
    fp.save(fig, out)


def plot_rough(rows, out):
    """W (J) against q per group of the other varied keys; mean over seeds, min-max band."""
    # sweep.csv: member, dir, the varied keys, status, ...: group by the varied keys except
    # the amplitude (the x axis) and the seed (averaged over).
    cols = list(rows[0])
    varied = cols[cols.index("dir") + 1:cols.index("status")]
    keys = [k for k in varied if k not in ("load.amplitude", "surface.seed")]
    groups = {}
    for r in rows:
        label = ", ".join(f"{k} = {r[k]}" for k in keys) or "all"
        groups.setdefault(label, {}).setdefault(float(r["load.amplitude"]), []).append(
            float(r["dissipated_energy"]))
    fig, axs = fp.figure(width=4.2, height=3.2)
    ax = axs[0, 0]
    print("group, q, W mean (J), W min, W max, seeds")
    for i, (label, by_q) in enumerate(sorted(groups.items())):
        q = np.array(sorted(by_q))
        W = [np.array(by_q[x]) for x in q]
        mean = np.array([w.mean() for w in W])
        ax.loglog(q, mean, "o-", color=f"C{i}", label=label)
        ax.fill_between(q, [w.min() for w in W], [w.max() for w in W], color=f"C{i}", alpha=0.2)
        for x, w in zip(q, W):
            print(f"{label}, {x:.4g}, {w.mean():.6g}, {w.min():.6g}, {w.max():.6g}, {len(w)}")
        q0, W0 = q[0], mean[0]
    qq = np.logspace(np.log10(q0), np.log10(0.3), 20)
    ax.loglog(qq, W0 * (qq / q0) ** 3, "k:", lw=1, label="slope 3")
    ax.set_xlabel("Q*/(μP)")
    ax.set_ylabel("energy per cycle W (J)")
    ax.set_title("energy per cycle, rough surfaces (mean, range over seeds)")
    ax.legend()
    fp.save(fig, out)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("study_dir")
    ap.add_argument("--out", default=None)
    args = ap.parse_args()
    rows = finished_rows(args.study_dir, TOOL)
    if "load.amplitude" not in rows[0]:
        fp.fail(TOOL, "load.amplitude is not varied in this study")
    scn = fp.read_scenario(os.path.join(args.study_dir, rows[0]["dir"]))
    out = args.out or os.path.join(args.study_dir, "energy_per_cycle.png")
    if fp.Contact(scn).hertz_ok:
        plot_sphere(rows, scn, out)
    else:
        plot_rough(rows, out)


if __name__ == "__main__":
    main()
