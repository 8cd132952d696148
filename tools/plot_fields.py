#!/usr/bin/python3
"""Maps of a saved field of a fretbem run at several steps (the stick/slip/open state is the
paper's Fig. 5).

usage: tools/plot_fields.py RUN_DIR [--steps 5,10,19] [--field state] [--out FILE.png]

Fields (result.h5, `output.fields`): state (open / stick / slip), pressure and traction_x/y
(MPa), slip_x/y (net slip since the start of the run, nm), dissipation (energy dissipated per
unit area since the start, J/m²), wear (worn depth, nm). Axes in µm from the domain centre;
each panel is titled with its step's F_x/(mu F_z) and U_x. Steps default to up to six saved
steps spread over the run, turning points first. Writes FILE.png and FILE.pdf (default
RUN_DIR/FIELD.png).
"""
import argparse
import os

import numpy as np
from matplotlib.colors import ListedColormap
from matplotlib.patches import Patch

import fretbem_plot as fp

TOOL = "plot_fields"

# name: (colour-bar label, factor from SI)
UNITS = {
    "pressure": ("pressure (MPa)", 1e-6),
    "traction_x": ("traction $\\tau_x$ (MPa)", 1e-6),
    "traction_y": ("traction $\\tau_y$ (MPa)", 1e-6),
    "slip_x": ("net slip $s_x$ since start (nm)", 1e9),
    "slip_y": ("net slip $s_y$ since start (nm)", 1e9),
    "dissipation": ("dissipated since start (J/m²)", 1.0),
    "wear": ("worn depth (nm)", 1e9),
}


def saved_steps(h5):
    if "fields" not in h5 or not len(h5["fields"]):
        fp.fail(TOOL, "no fields saved (set output.fields in the scenario)")
    return sorted(int(k.split("_")[1]) for k in h5["fields"])


def default_steps(saved, ts, most=6):
    """Up to `most` saved steps spread over the run, turning points preferred."""
    turning = [s for s in saved if "turning" in ts and s < len(ts["turning"])
               and ts["turning"][s] == 1]
    rest = [s for s in saved if s not in turning]
    pool = turning if len(turning) >= most else sorted(turning + rest)
    pick = np.unique(np.linspace(0, len(pool) - 1, min(most, len(pool))).round().astype(int))
    chosen = sorted(set(pool[i] for i in pick) | set(turning[:most]))
    return chosen[:most] if len(chosen) > most else chosen


def panel_title(ts, step, mu):
    if step >= len(ts["Fx"]):
        return f"step {step}"
    f = ts["Fx"][step] / (mu * ts["Fz"][step]) if mu else float("nan")
    return f"step {step}: $F_x/\\mu F_z$ = {f:+.2f}, $U_x$ = {ts['Ux'][step] * 1e9:.3g} nm"


def draw(fig, ax, field, a, extent):
    ax.grid(False)
    if field == "state":
        cmap = ListedColormap(["white", "black", "0.6"])
        ax.imshow(a, origin="lower", cmap=cmap, vmin=-0.5, vmax=2.5, interpolation="nearest",
                  extent=extent)
        return
    label, factor = UNITS.get(field, (field, 1.0))
    im = ax.imshow(a * factor, origin="lower", cmap="viridis", interpolation="nearest",
                   extent=extent)
    fig.colorbar(im, ax=ax, shrink=0.85, label=label)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("run_dir")
    ap.add_argument("--steps", default=None, help="comma-separated step numbers")
    ap.add_argument("--field", default="state")
    ap.add_argument("--out", default=None)
    args = ap.parse_args()
    scn = fp.read_scenario(args.run_dir)
    length, mu = fp.number(scn, "grid.length"), fp.number(scn, "material.mu", 0.3)
    ts = fp.read_csv(os.path.join(args.run_dir, "timeseries.csv"), TOOL)
    path = os.path.join(args.run_dir, "result.h5")
    if not os.path.exists(path):
        fp.fail(TOOL, f"{path}: not found")
    with fp.open_h5(path, TOOL) as h5:
        saved = saved_steps(h5)
        steps = [int(s) for s in args.steps.split(",")] if args.steps else \
            default_steps(saved, ts)
        ncols, nrows = fp.panel_grid(len(steps))
        fig, axes = fp.figure(ncols=ncols, nrows=nrows, width=2.9, height=2.9)
        for ax in axes.flat[len(steps):]:
            ax.set_visible(False)
        for ax, s in zip(axes.flat, steps):
            if s not in saved:
                fp.fail(TOOL, f"step {s} not saved; saved steps: {saved}")
            g = h5[f"fields/step_{s:06d}"]
            if args.field not in g:
                fp.fail(TOOL, f"step {s} has no field '{args.field}'; it has {list(g)}")
            a = np.asarray(g[args.field], dtype=float)  # array[j, i]: rows along y
            ny, nx = a.shape
            half_x = 0.5 * length * 1e6 if length else 0.5 * nx
            half_y = half_x * ny / nx
            draw(fig, ax, args.field, a, [-half_x, half_x, -half_y, half_y])
            ax.set_title(panel_title(ts, s, mu), fontsize=7)
            ax.set_xlabel("x (µm)" if length else "x (cells)")
        for row in axes:
            row[0].set_ylabel("y (µm)" if length else "y (cells)")
    if args.field == "state":
        axes[0][-1].legend(handles=[Patch(facecolor=c, edgecolor="k", label=n) for c, n in
                                    (("black", "stick"), ("0.6", "slip"), ("white", "open"))],
                           loc="upper left", bbox_to_anchor=(1.02, 1.0), frameon=False)
    out = args.out or os.path.join(args.run_dir, f"{args.field}.png")
    fp.save(fig, out)


if __name__ == "__main__":
    fp.guarded(main, TOOL)
