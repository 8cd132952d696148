#!/usr/bin/python3
"""Wear plots of a fretbem wear run: centre-line worn depth and pressure at several N, the
final worn-depth map, worn volume and energy per cycle against N (from DIR/result.h5 and
DIR/cycles.csv; only the rows with accepted = 1, the integrator's solution, not its stage or
trial evaluations).

usage: tools/plot_wear.py DIR [--out FILE.png]
Writes FILE.png and FILE.pdf (default DIR/wear.png).
"""
import argparse
import os

import h5py
import numpy as np

import fretbem_plot as fp


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("dir")
    ap.add_argument("--out", default=None, help="image file (default DIR/wear.png)")
    a = ap.parse_args()
    out = a.out or os.path.join(a.dir, "wear.png")
    with h5py.File(os.path.join(a.dir, "result.h5"), "r") as f:
        if "wear" not in f:
            fp.fail("plot_wear", f"{a.dir} is not a wear run (no /wear in result.h5)")
        z0 = f["surface/initial"][()]
        snaps = sorted(k for k in f["wear"].keys() if k.startswith("snapshot_"))
        N = [float(f["wear"][s].attrs["time"]) for s in snaps]
        worn = [f["wear"][s]["worn_depth"][()] for s in snaps]
        pres = [f["wear"][s]["pressure"][()] for s in snaps]
    length = fp.number(fp.read_scenario(a.dir), "grid.length")
    ny, nx = z0.shape
    h = length / nx
    x = (np.arange(nx) + 0.5 - 0.5 * nx) * h
    j = ny // 2
    wear = fp.read_csv(os.path.join(a.dir, "cycles.csv"), "plot_wear")
    keep = wear["accepted"] == 1
    wear = {k: v[keep] for k, v in wear.items()}

    fig, ax = fp.figure(ncols=3, nrows=2, width=3.6, height=3.0)
    pick = np.unique(np.linspace(0, len(N) - 1, min(len(N), 6)).round().astype(int))
    cmap = fp.plt.get_cmap("viridis")
    for c, i in enumerate(pick):
        col = cmap(c / max(1, len(pick) - 1))
        ax[0, 0].plot(x * 1e6, -worn[i][j] * 1e9, color=col, label=f"N = {N[i]:.6g}")
        ax[0, 1].plot(x * 1e6, pres[i][j] / 1e6, color=col, label=f"N = {N[i]:.6g}")
    # The gap's change -W (the indenter's profile change z - z0 when only it wears): on the
    # scale of the indenter it would not be visible.
    ax[0, 0].set(xlabel="x (µm)", ylabel="-W (nm)", title="centre-line worn depth (both bodies)")
    ax[0, 0].legend(fontsize=7, loc="lower center")
    ax[0, 1].set(xlabel="x (µm)", ylabel="pressure (MPa)", title="centre-line pressure")
    ax[0, 1].legend(fontsize=7, loc="lower center")
    ext = [x[0] * 1e6, x[-1] * 1e6, x[0] * 1e6, x[-1] * 1e6]
    ax[1, 0].grid(False)
    im = ax[1, 0].imshow(worn[-1] * 1e9, origin="lower", extent=ext, cmap="magma")
    fig.colorbar(im, ax=ax[1, 0], label="worn depth (nm)")
    ax[1, 0].set(xlabel="x (µm)", ylabel="y (µm)", title=f"worn depth at N = {N[-1]:.6g}")
    ax[1, 1].plot(wear["N"], wear["wear_volume"], ".-", ms=3, label="total")
    if np.any(wear["wear_volume_half_space"] > 0):  # both bodies wear (wear.indenter_share)
        ax[1, 1].plot(wear["N"], wear["wear_volume_indenter"], "--", label="indenter")
        ax[1, 1].plot(wear["N"], wear["wear_volume_half_space"], ":", label="half-space")
        ax[1, 1].legend(fontsize=8)
    ax[1, 1].set(xlabel="cycles N", ylabel="worn volume (m³)", title="wear volume")
    ax[0, 2].plot(wear["N"], wear["energy_per_cycle"], ".-", ms=3)
    ax[0, 2].set(xlabel="cycles N", ylabel="energy per cycle (J)",
                 title="frictional energy per cycle")
    ax[1, 2].plot(wear["N"], wear["contact_radius"] * 1e6, ".-", ms=3, label="contact radius")
    ax[1, 2].set(xlabel="cycles N", ylabel="radius (µm)", title="contact radius")
    for axis in (ax[0, 2], ax[1, 1], ax[1, 2]):
        if wear["N"].max() > 100:
            axis.set_xscale("symlog", linthresh=1)
    fp.save(fig, out)


if __name__ == "__main__":
    main()
