#!/usr/bin/python3
"""Energy dissipated per steady cycle against the tangential amplitude Q*/(mu P), log-log, from a
fretbem sweep over load.amplitude (sweep.csv): a sphere next to Mindlin-Deresiewicz, or rough
surfaces (one curve per value of the other varied keys, mean over surface.seed with the
seeds' range as a band, a slope-3 guide).

usage: tools/plot_energy_per_cycle.py STUDY_DIR [--out energy.png]

Closed form (Johnson, Contact Mechanics, eq. 7.60, in fretbem's E*, G*): for a rigid sphere,
a = (3 P R / 4 E*)^(1/3), delta = a^2/R, u* = mu delta E*/G*, q = Q*/(mu P):
  W(q) = (24/5) mu P u* [1 - (1-q)^(5/3) - (5q/6) (1 + (1-q)^(2/3))]  ~  (4/27) mu P u* q^3
(slope 3 at small q). The slip annulus is a (1 - (1-q)^(1/3)) wide: the grid resolves it with
at least two cells only where that exceeds 2h; points below are drawn hollow. Prints one line
per member: q, W simulated, W closed form, ratio, annulus width in cells.
"""
import argparse
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from sweep_results import finished_rows, resolved_scenario  # noqa: E402


def mindlin(cp):
    E, nu = float(cp["material"]["E"]), float(cp["material"]["nu"])
    mu = float(cp["material"]["mu"])
    if cp["material"].get("E2", "").strip():
        sys.exit("plot_energy_per_cycle: a second elastic body is not handled here")
    if cp["surface"]["type"].strip() != "sphere":
        return None
    R = float(cp["surface"]["radius"])
    P = float(cp["load"]["normal_force"])
    E_star = E / (1 - nu**2)
    G_star = 2 * E / ((1 + nu) * (2 - nu))  # 4G/(2 - nu), rigid indenter
    a = (3 * P * R / (4 * E_star)) ** (1 / 3)
    ustar = mu * a * a / R * E_star / G_star
    h = float(cp["grid"]["length"]) / int(cp["grid"]["n"])
    return mu * P, ustar, a, h


def energy(muP, ustar, q):
    q = np.asarray(q, dtype=float)
    return 24 / 5 * muP * ustar * (1 - (1 - q) ** (5 / 3) - 5 * q / 6 * (1 + (1 - q) ** (2 / 3)))


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
    fig, ax = plt.subplots(figsize=(6, 4.5))
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
    ax.set_title("energy per cycle, rough surfaces (mean and range over seeds)")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out, dpi=120)
    print(f"plot_energy_per_cycle: wrote {out}")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("study_dir")
    ap.add_argument("--out", default=None)
    args = ap.parse_args()
    rows = finished_rows(args.study_dir, "plot_energy_per_cycle")
    if "load.amplitude" not in rows[0]:
        sys.exit("plot_energy_per_cycle: load.amplitude is not varied in this study")
    model = mindlin(resolved_scenario(os.path.join(args.study_dir, rows[0]["dir"])))
    out = args.out or os.path.join(args.study_dir, "energy_per_cycle.png")
    if model is None:
        return plot_rough(rows, out)
    muP, ustar, a, h = model
    q = np.array([float(r["load.amplitude"]) for r in rows])
    W = np.array([float(r["dissipated_energy"]) for r in rows])
    ring = a * (1 - (1 - q) ** (1 / 3)) / h
    Wmd = energy(muP, ustar, q)
    print("q, W (J), W Mindlin-Deresiewicz (J), ratio, slip annulus (cells)")
    for i in np.argsort(q):
        print(f"{q[i]:.4g}, {W[i]:.6g}, {Wmd[i]:.6g}, {W[i] / Wmd[i]:.4f}, {ring[i]:.2f}")
    fig, ax = plt.subplots(figsize=(6, 4.5))
    qq = np.logspace(np.log10(min(q.min(), 0.01)), np.log10(0.999), 200)
    ax.loglog(qq, energy(muP, ustar, qq) / (muP * ustar), "k-", lw=1, label="Mindlin–Deresiewicz")
    ax.loglog(qq, 4 / 27 * qq**3, "k:", lw=1, label="slope 3: (4/27) q³")
    ok = ring >= 2
    ax.loglog(q[ok], W[ok] / (muP * ustar), "o", color="C0", label="fretbem (annulus ≥ 2 cells)")
    ax.loglog(q[~ok], W[~ok] / (muP * ustar), "o", mfc="none", color="C0",
              label="fretbem (annulus < 2 cells)")
    ax.set_xlabel("Q*/(μP)")
    ax.set_ylabel("W / (μP u*)")
    ax.set_title(f"energy per cycle, sphere, a/h = {a / h:.0f}")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out, dpi=120)
    print(f"plot_energy_per_cycle: wrote {out}")


if __name__ == "__main__":
    main()
