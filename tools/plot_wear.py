#!/usr/bin/python3
"""Wear plots of a fretbem wear run: centre-line worn depth and pressure at several N, the
final worn-depth map, worn volume and energy per cycle against N (from DIR/result.h5 and
DIR/cycles.csv; only the rows with accepted = 1, the integrator's solution, not its stage or
trial evaluations), and the hysteresis loop F_x - U_x at given N.

usage: tools/plot_wear.py DIR [--out FILE.png] [--loop-at N1,N2,...] [--loop-out FILE.png]
Writes FILE.png and FILE.pdf (default DIR/wear.png), and the loops as LOOP.png and LOOP.pdf
(default DIR/wear_loops.png). --loop-at picks, for each N, the accepted cycle nearest to it
(default: the first and the last accepted cycle and one between) and draws the rows of that
simulated cycle from DIR/timeseries.csv (cycles.csv's row i, accepted or not, wrote the rows with
time in (i, i + 1], in both integrator modes), labelled with its energy per cycle. Wear runs
solve each monotone segment of the period in one increment, so these rows are the cycle's
turning points, not the branches of the loop between them.
"""
import argparse
import os

import h5py
import numpy as np

import fretbem_plot as fp

TOOL = "plot_wear"


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("dir")
    ap.add_argument("--out", default=None, help="image file (default DIR/wear.png)")
    ap.add_argument("--loop-at", default=None, help="cycle counts N1,N2,... of the loops")
    ap.add_argument("--loop-out", default=None, help="loop figure (default DIR/wear_loops.png)")
    a = ap.parse_args()
    out = a.out or os.path.join(a.dir, "wear.png")
    with h5py.File(os.path.join(a.dir, "result.h5"), "r") as f:
        if "wear" not in f:
            fp.fail(TOOL, f"{a.dir} is not a wear run (no /wear in result.h5)")
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
    wear["row"] = np.arange(len(wear["N"]))  # position in cycles.csv: the loop's time
    keep = wear["accepted"] == 1
    wear = {k: v[keep] for k, v in wear.items()}

    fig, ax = fp.figure(ncols=3, nrows=2, width=3.6, height=3.0)
    pick = np.unique(np.linspace(0, len(N) - 1, min(len(N), 6)).round().astype(int))
    cmap = fp.plt.get_cmap("viridis")
    for c, i in enumerate(pick):
        col = cmap(c / max(1, len(pick) - 1))
        ax[0, 0].plot(x * 1e6, -worn[i][j] * 1e9, color=col, label=f"N = {fp.count(N[i])}")
        ax[0, 1].plot(x * 1e6, pres[i][j] / 1e6, color=col, label=f"N = {fp.count(N[i])}")
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
    ax[1, 0].set(xlabel="x (µm)", ylabel="y (µm)", title=f"worn depth at N = {fp.count(N[-1])}")
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
    plot_loops(a, wear)


def loop_cycles(spec, N):
    """Indices of the accepted rows nearest to the wanted counts (default: first, middle, last)."""
    if spec is None:
        return sorted({0, len(N) // 2, len(N) - 1})
    try:
        wanted = [float(v) for v in spec.split(",")]
    except ValueError:
        fp.fail(TOOL, f"--loop-at: '{spec}' is not a list of cycle counts N1,N2,...")
    out = []
    for w in wanted:
        if not N.min() - 0.5 <= w <= N.max() + 0.5:
            fp.fail(TOOL, f"--loop-at: N = {fp.count(w)} is outside the run's "
                          f"{fp.count(N.min())}..{fp.count(N.max())}")
        out.append(int(np.argmin(np.abs(N - w))))
    return out


def loop_rows(time, i):
    """Row indices of DIR/timeseries.csv that draw the loop of DIR/cycles.csv's row i.

    Every cycles.csv row, accepted or not, is one simulated cycle whose timeseries rows have
    time = its position i + phase (docs/wear.md): ARKODE's steady cycle writes its loop from
    the first turning point (phase 0) round to it again (the virgin loading is not written),
    the cycle-by-cycle mode one period. Its rows are those with time in (i, i + 1]; the loop
    starts where the last of them ends (same loads, a closed steady loop), drawn first.
    Checked against runs in tests/plot_tools_test.py (the dissipation along the rows is the
    cycle's energy)."""
    rows = np.flatnonzero((time > i + 1e-9) & (time <= i + 1 + 1e-9))
    return np.concatenate([rows[-1:], rows]) if len(rows) else rows


def plot_loops(a, wear):
    ts = fp.read_csv(os.path.join(a.dir, "timeseries.csv"), TOOL)
    fig, ax = fp.figure(width=3.6, height=3.0)
    ax = ax[0, 0]
    pick = loop_cycles(a.loop_at, wear["N"])
    cmap = fp.plt.get_cmap("viridis")
    for c, i in enumerate(pick):
        # i indexes the accepted rows; the loop's time is the row's position in cycles.csv.
        rows = loop_rows(ts["time"], wear["row"][i])
        col = cmap(c / max(1, len(pick) - 1))
        label = f"N = {fp.count(wear['N'][i])}: {wear['energy_per_cycle'][i]:.3g} J/cycle"
        ax.plot(ts["Ux"][rows] * 1e6, ts["Fx"][rows], ".-", ms=3, color=col, label=label)
    # Wear runs solve each monotone segment in one increment (docs/wear.md, "Steps
    # simulated"): the rows are the cycle's turning points, not the branches between them.
    ax.set(xlabel="U$_x$ (µm)", ylabel="F$_x$ (N)",
           title="turning points of the cycle at N")
    ax.legend(fontsize=7)
    fp.save(fig, a.loop_out or os.path.join(a.dir, "wear_loops.png"))


if __name__ == "__main__":
    main()
