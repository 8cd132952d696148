#!/usr/bin/python3
"""Pareto front of error against run time from bench_accuracy_vs_time's CSV
(docs/performance.md, "Run time against error").

Usage: tools/plot_bench.py RESULTS.csv [--out FILE.png] [--time cpu|wall]

One panel per case (hertz, cattaneo, mindlin): every (n, tolerance) point, coloured by n with
the tolerance as marker (hollow: float FFTs, from the optional `fft` column; rows without it
are double), and the Pareto front over all points (the points no other point beats in both
error and time) as a line. CPU time is the default axis: on a shared machine wall time includes
waiting for other processes.
"""
import argparse
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read(path):
    rows = []
    with open(path) as f:
        for r in csv.DictReader(line for line in f if not line.startswith("#")):
            row = {k: (v if k in ("case", "fft") else float(v)) for k, v in r.items()}
            row.setdefault("fft", "double")
            rows.append(row)
    return rows


def pareto(points):
    """Points (time, error) not dominated by any other, sorted by time."""
    front, best = [], float("inf")
    for t, e in sorted(points):
        if e < best:
            front.append((t, e))
            best = e
    return front


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("csv")
    ap.add_argument("--out", default="accuracy_vs_time.png")
    ap.add_argument("--time", choices=["cpu", "wall"], default="cpu")
    a = ap.parse_args()
    rows = read(a.csv)
    if not rows:
        sys.exit(f"{a.csv}: no rows")
    key = "cpu_s" if a.time == "cpu" else "wall_s"
    cases = [c for c in ("hertz", "cattaneo", "mindlin") if any(r["case"] == c for r in rows)]
    labels = {"hertz": "Hertz |F/F_H - 1|", "cattaneo": "Cattaneo max |U/U_M - 1|",
              "mindlin": "Mindlin-Deresiewicz |W/W_MD - 1|"}
    ns = sorted({int(r["n"]) for r in rows})
    tols = sorted({r["tol"] for r in rows}, reverse=True)
    markers = "osD^v<>"
    cmap = plt.get_cmap("viridis")
    fig, axes = plt.subplots(1, len(cases), figsize=(5 * len(cases), 4.2), squeeze=False)
    for ax, case in zip(axes[0], cases):
        sub = [r for r in rows if r["case"] == case]
        for r in sub:
            colour = cmap(ns.index(int(r["n"])) / max(1, len(ns) - 1))
            ax.loglog(r[key], max(r["error"], 1e-16), markers[tols.index(r["tol"]) % 7],
                      color=colour, ms=6, alpha=0.85,
                      mfc="none" if r["fft"] == "float" else colour)
        front = pareto([(r[key], max(r["error"], 1e-16)) for r in sub])
        ax.loglog(*zip(*front), "k-", lw=1, label="Pareto front")
        ax.set_title(labels[case])
        ax.set_xlabel(f"{a.time.upper()} time of the run (s)")
        ax.set_ylabel("error vs closed form")
        ax.grid(True, which="both", alpha=0.3)
    for i, n in enumerate(ns):
        axes[0][0].plot([], [], "s", color=cmap(i / max(1, len(ns) - 1)), label=f"n = {n}")
    for j, t in enumerate(tols):
        axes[0][0].plot([], [], markers[j % 7], color="gray", label=f"tol = {t:.0e}")
    if any(r["fft"] == "float" for r in rows):
        axes[0][0].plot([], [], "o", color="gray", mfc="none", label="float FFTs")
    axes[0][0].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(a.out, dpi=120)
    print(a.out)


if __name__ == "__main__":
    main()
