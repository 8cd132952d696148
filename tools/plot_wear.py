#!/usr/bin/python3
"""Wear plots of a fretbem wear run: centre-line worn depth and pressure at several N, the
final worn-depth map, worn volume and energy per cycle against N (from DIR/result.h5 and
DIR/cycles.csv; only the rows with accepted = 1, the integrator's solution, not its stage or
trial evaluations), and the hysteresis loop F_x - U_x at given N.

usage: tools/plot_wear.py DIR [--out FILE.png] [--loop-at N1,N2,...] [--loop-out FILE.png]
Writes FILE.png and FILE.pdf (default DIR/wear.png), and the loops as LOOP.png and LOOP.pdf
(default DIR/wear_loops.png). --loop-at N draws the steady F_x - U_x loop at each N (default: the
first, a middle and the last accepted N) with its area: the second cycle of a plain fretting run
(no wear law, 64 steps per cycle) on the surface worn to the wear snapshot nearest N, run with
the fretbem binary --fretbem PATH (default build/fretbem next to tools/, else on PATH); see
loop_at. DIR/timeseries.csv holds only the turning points of the simulated cycles (wear runs
solve each monotone segment in one increment; loop_rows picks them, used by the tests).
"""
import argparse
import os

import numpy as np

import fretbem_plot as fp

TOOL = "plot_wear"


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("dir")
    ap.add_argument("--out", default=None, help="image file (default DIR/wear.png)")
    ap.add_argument("--loop-at", default=None, help="cycle counts N1,N2,... of the loops")
    ap.add_argument("--loop-out", default=None, help="loop figure (default DIR/wear_loops.png)")
    ap.add_argument("--fretbem", default=None,
                    help="fretbem binary for the loops (default build/fretbem, else PATH)")
    a = ap.parse_args()
    out = a.out or os.path.join(a.dir, "wear.png")
    with fp.open_h5(os.path.join(a.dir, "result.h5"), TOOL) as f:
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


def loop_wanted(spec, N):
    """The wanted cycle counts (default: the first, a middle and the last accepted N)."""
    if spec is None:
        return [float(N[i]) for i in sorted({0, len(N) // 2, len(N) - 1})]
    try:
        wanted = [float(v) for v in spec.split(",")]
    except ValueError:
        fp.fail(TOOL, f"--loop-at: '{spec}' is not a list of cycle counts N1,N2,...")
    out = []
    for w in wanted:
        if not N.min() - 0.5 <= w <= N.max() + 0.5:
            fp.fail(TOOL, f"--loop-at: N = {fp.count(w)} is outside the run's "
                          f"{fp.count(N.min())}..{fp.count(N.max())}")
        out.append(w)
    return out


def loop_rows(time, i):
    """Row indices of DIR/timeseries.csv (the turning points) of DIR/cycles.csv's row i.

    Every cycles.csv row, accepted or not, is one simulated cycle whose timeseries rows have
    time = its position i + phase (docs/wear.md): ARKODE's steady cycle writes its loop from
    the first turning point (phase 0) round to it again (the virgin loading is not written),
    the cycle-by-cycle mode one period. Its rows are those with time in (i, i + 1]; the loop
    starts where the last of them ends (same loads, a closed steady loop), drawn first.
    Checked against runs in tests/plot_tools_test.py (the dissipation along the rows is the
    cycle's energy)."""
    rows = np.flatnonzero((time > i + 1e-9) & (time <= i + 1 + 1e-9))
    return np.concatenate([rows[-1:], rows]) if len(rows) else rows


def fretbem_binary(spec):
    """--fretbem PATH, else build/fretbem next to tools/, else fretbem on PATH."""
    import shutil

    if spec:
        if not os.access(spec, os.X_OK):
            fp.fail(TOOL, f"--fretbem: {spec} is not an executable file")
        return spec
    local = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "build", "fretbem")
    found = local if os.access(local, os.X_OK) else shutil.which("fretbem")
    if not found:
        fp.fail(TOOL, "--loop-at: no fretbem binary (give --fretbem PATH)")
    return found


def nearest_snapshot(wanted, times):
    """Index of the wear snapshot nearest to N = wanted in log(1 + N). Snapshots are written at
    N = 0, 1, 2, 5, 10, ... (factor <= 2.5 apart), so any N inside the run is within a factor
    sqrt(2.5) ~ 1.6 of one; farther than a factor 2 (the worn depth, ~linear in N early on, would
    differ by more than 2x) is refused."""
    t = np.asarray(times)
    d = np.abs(np.log1p(t) - np.log1p(wanted))
    i = int(np.argmin(d))
    if d[i] > np.log(2):
        fp.fail(TOOL, f"--loop-at: no wear snapshot within a factor 2 of N = {fp.count(wanted)} "
                      f"(snapshots at N = {', '.join(fp.count(v) for v in t)})")
    return i


def loop_scenario(text, surface_file, out_dir, steps):
    """The run's resolved scenario without [wear], on the worn surface, two cycles of `steps`
    steps each (plain fretting: the loop at N is the second cycle, see loop_at)."""
    out, section = [], None
    for line in text.splitlines():
        s = line.strip()
        if s.startswith("["):
            section = s.strip("[] ")
            if section == "wear":
                continue
        if section == "wear":
            continue
        key = s.split("=", 1)[0].strip() if "=" in s and not s.startswith("#") else None
        if (section, key) in (("surface", "type"), ("surface", "file"), ("surface", "dataset"),
                              ("surface", "layout"), ("load", "cycles"),
                              ("load", "steps_per_cycle"), ("load", "steps"), ("output", "dir"),
                              ("output", "fields")):
            continue
        out.append(line)
        if s == "[surface]":
            out += ["type = file", f"file = {surface_file}", "layout = yx"]
        elif s == "[load]":
            out += ["cycles = 2", f"steps_per_cycle = {steps}"]
        elif s == "[output]":
            out += [f"dir = {out_dir}", "fields = none"]
    return "\n".join(out) + "\n"


def loop_at(run_dir, wanted, binary, work, steps=64):
    """The steady F_x - U_x loop at N = wanted: (N used, Ux, Fx, area, dissipation).

    Under a periodic tangential load at constant normal load the steady cycle does not depend
    on the initial tangential state (Barber, Davies & Hills, Int. J. Solids Struct. 48 (2011)
    2041; for the sphere Mindlin & Deresiewicz 1953, Masing's rule), so the loop at N is the
    second cycle of a plain fretting run (no wear law) on the surface worn to N: the initial
    indenter height minus the total worn depth (both bodies' shares: the gap sees their sum)."""
    import subprocess

    with fp.open_h5(os.path.join(run_dir, "result.h5"), TOOL) as f:
        snaps = sorted(k for k in f["wear"].keys() if k.startswith("snapshot_"))
        times = [float(f["wear"][s].attrs["time"]) for s in snaps]
        i = nearest_snapshot(wanted, times)
        z = f["surface/initial"][()] - f["wear"][snaps[i]]["worn_depth"][()]
        text = f["scenario"][()]
        text = text.decode() if isinstance(text, bytes) else str(text)
    tag = f"N{fp.count(times[i])}"
    surface = os.path.abspath(os.path.join(work, f"worn_{tag}.npy"))
    np.save(surface, z)
    ini = os.path.join(work, f"loop_{tag}.ini")
    out = os.path.join(work, f"loop_{tag}")
    with open(ini, "w") as fh:
        fh.write(loop_scenario(text, surface, out, steps))
    r = subprocess.run([binary, "run", ini, "--quiet", "--overwrite", "--out", out],
                       capture_output=True,
                       text=True)
    if r.returncode != 0:
        fp.fail(TOOL, f"--loop-at: fretbem run on the surface worn to N = {fp.count(times[i])} "
                      f"failed: {r.stderr.strip().splitlines()[-1] if r.stderr.strip() else ''}")
    ts = fp.read_csv(os.path.join(out, "timeseries.csv"), TOOL)
    rows = np.flatnonzero(ts["time"] >= 1 - 1e-9)  # the second cycle, from its start point
    ux, fx = ts["Ux"][rows], ts["Fx"][rows]
    # Shoelace area of the closed polygon (a counter-clockwise F-U loop dissipates +area).
    area = abs(0.5 * np.sum(ux * np.roll(fx, -1) - np.roll(ux, -1) * fx))
    dissipated = ts["dissipation"][rows[-1]] - ts["dissipation"][rows[0]]
    return times[i], ux, fx, area, dissipated


def plot_loops(a, wear):
    import tempfile

    fig, ax = fp.figure(width=3.6, height=3.0)
    ax = ax[0, 0]
    wanted = loop_wanted(a.loop_at, wear["N"])
    binary = fretbem_binary(a.fretbem)
    cmap = fp.plt.get_cmap("viridis")
    with tempfile.TemporaryDirectory(prefix="fretbem_loop_") as work:
        for c, w in enumerate(wanted):
            n_used, ux, fx, area, _ = loop_at(a.dir, w, binary, work)
            col = cmap(c / max(1, len(wanted) - 1))
            label = f"N = {fp.count(n_used)}" + ("" if n_used == w else
                                                   f" (nearest to {fp.count(w)})")
            ax.plot(ux * 1e6, fx, "-", color=col, label=f"{label}: area {area:.3g} J")
    ax.set(xlabel="U$_x$ (µm)", ylabel="F$_x$ (N)", title="hysteresis loop at N")
    ax.legend(fontsize=7)
    fp.save(fig, a.loop_out or os.path.join(a.dir, "wear_loops.png"))


if __name__ == "__main__":
    fp.guarded(main, TOOL)
