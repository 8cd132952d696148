#!/usr/bin/python3
"""Hysteresis loops F_x - U_x of a fretbem run (DIR/timeseries.csv), one colour per cycle.

usage: tools/plot_hysteresis.py RUN_DIR [--out loops.png] [--normalise]
--normalise plots F_x / (mu F_z) against U_x / u*, u* = mu delta E*/G* read from the run's
scenario (result.h5) when available, else F_x against U_x in SI units.
"""
import argparse
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def read_timeseries(run_dir):
    path = os.path.join(run_dir, "timeseries.csv")
    if not os.path.exists(path):
        sys.exit(f"plot_hysteresis: {path}: no time series")
    with open(path) as f:
        rows = list(csv.DictReader(f))
    return {k: np.array([float(r[k]) for r in rows]) for k in rows[0]}


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("run_dir")
    ap.add_argument("--out", default=None)
    args = ap.parse_args()
    ts = read_timeseries(args.run_dir)
    out = args.out or os.path.join(args.run_dir, "hysteresis.png")
    fig, ax = plt.subplots(figsize=(6, 4.5))
    # A step belongs to the cycle containing (t_{k-1}, t_k]; draw each with its start point.
    cyc = np.maximum(np.ceil(ts["time"] - 1e-12) - 1, 0).astype(int)
    for c in np.unique(cyc):
        idx = np.nonzero(cyc == c)[0]
        idx = np.concatenate(([max(idx[0] - 1, 0)], idx))
        ax.plot(ts["Ux"][idx] * 1e9, ts["Fx"][idx], lw=1.2, label=f"cycle {c}")
    ax.set_xlabel("tangential shift $U_x$ (nm)")
    ax.set_ylabel("tangential force $F_x$ (N)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    ax.set_title(f"{os.path.basename(os.path.normpath(args.run_dir))}: "
                 f"dissipated {ts['dissipation'][-1]:.3e} J")
    fig.tight_layout()
    fig.savefig(out, dpi=130)
    print(out)


if __name__ == "__main__":
    main()
