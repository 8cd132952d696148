#!/usr/bin/python3
"""Wear plots of a fretbem wear run: centre-line profile and pressure sections at several N,
the final worn-depth map, and wear volume against N (from DIR/result.h5 and DIR/cycles.csv;
only the rows with accepted = 1, the integrator's solution, not its stage or trial
evaluations).

usage: tools/plot_wear.py DIR [--out FILE.png]
"""
import argparse
import os

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def read_scenario_value(text, section, key, default=None):
    sec = None
    for line in text.splitlines():
        line = line.split("#")[0].strip()
        if line.startswith("["):
            sec = line.strip("[]")
        elif "=" in line and sec == section:
            k, v = (s.strip() for s in line.split("=", 1))
            if k == key:
                return v
    return default


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("dir")
    ap.add_argument("--out", default=None, help="image file (default DIR/wear.png)")
    a = ap.parse_args()
    out = a.out or os.path.join(a.dir, "wear.png")
    with h5py.File(os.path.join(a.dir, "result.h5"), "r") as f:
        text = f["scenario"][()]
        text = text.decode() if isinstance(text, bytes) else text
        z0 = f["surface/initial"][()]
        snaps = sorted(k for k in f["wear"].keys() if k.startswith("snapshot_"))
        N = [float(f["wear"][s].attrs["time"]) for s in snaps]
        worn = [f["wear"][s]["worn_depth"][()] for s in snaps]
        pres = [f["wear"][s]["pressure"][()] for s in snaps]
    length = float(read_scenario_value(text, "grid", "length"))
    ny, nx = z0.shape
    h = length / nx
    x = (np.arange(nx) + 0.5 - 0.5 * nx) * h
    j = ny // 2
    wear = np.genfromtxt(os.path.join(a.dir, "cycles.csv"), delimiter=",", names=True)
    wear = np.atleast_1d(wear)
    wear = wear[wear["accepted"] == 1]

    fig, ax = plt.subplots(2, 2, figsize=(11, 8))
    pick = np.unique(np.linspace(0, len(N) - 1, min(len(N), 6)).round().astype(int))
    cmap = plt.get_cmap("viridis")
    for c, i in enumerate(pick):
        col = cmap(c / max(1, len(pick) - 1))
        ax[0, 0].plot(x * 1e6, -worn[i][j] * 1e9, color=col, label=f"N = {N[i]:.3g}")
        ax[0, 1].plot(x * 1e6, pres[i][j] / 1e6, color=col, label=f"N = {N[i]:.3g}")
    # The gap's change -W (the indenter's profile change z - z0 when only it wears): on the
    # scale of the indenter it would not be visible.
    ax[0, 0].set(xlabel="x (µm)", ylabel="-W (nm)", title="centre-line worn depth (both bodies)")
    ax[0, 0].legend(fontsize=8)
    ax[0, 1].set(xlabel="x (µm)", ylabel="pressure (MPa)", title="centre-line pressure")
    ax[0, 1].legend(fontsize=8)
    ext = [x[0] * 1e6, x[-1] * 1e6, x[0] * 1e6, x[-1] * 1e6]
    im = ax[1, 0].imshow(worn[-1] * 1e9, origin="lower", extent=ext, cmap="magma")
    fig.colorbar(im, ax=ax[1, 0], label="worn depth (nm)")
    ax[1, 0].set(xlabel="x (µm)", ylabel="y (µm)", title=f"worn depth at N = {N[-1]:.3g}")
    ax[1, 1].plot(wear["N"], wear["wear_volume"], ".-", ms=3, label="total")
    if np.any(wear["wear_volume_half_space"] > 0):  # both bodies wear (wear.indenter_share)
        ax[1, 1].plot(wear["N"], wear["wear_volume_indenter"], "--", label="indenter")
        ax[1, 1].plot(wear["N"], wear["wear_volume_half_space"], ":", label="half-space")
        ax[1, 1].legend(fontsize=8)
    ax[1, 1].set(xlabel="cycles N", ylabel="worn volume (m³)", title="wear volume")
    if wear["N"].max() > 100:
        ax[1, 1].set_xscale("symlog", linthresh=1)
    fig.tight_layout()
    fig.savefig(out, dpi=120)
    print(out)


if __name__ == "__main__":
    main()
