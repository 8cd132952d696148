#!/usr/bin/python3
"""Stick / slip / open map of saved steps of a fretbem run (like Fig. 5 of the paper).

usage: tools/plot_fields.py RUN_DIR [--steps 5,10,19] [--field state] [--out fields.png]
Black: stick, grey: slip, white: open (field `state`); any other saved field (pressure,
traction_x, ...) is drawn with a colour map. Steps default to every saved step (at most 6).
"""
import argparse
import os
import sys

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.colors import ListedColormap  # noqa: E402


def saved_steps(h5):
    if "fields" not in h5:
        sys.exit("plot_fields: no fields saved (set output.fields in the scenario)")
    return sorted(int(k.split("_")[1]) for k in h5["fields"])


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("run_dir")
    ap.add_argument("--steps", default=None)
    ap.add_argument("--field", default="state")
    ap.add_argument("--out", default=None)
    args = ap.parse_args()
    path = os.path.join(args.run_dir, "result.h5")
    with h5py.File(path, "r") as h5:
        steps = saved_steps(h5)
        if args.steps:
            steps = [int(s) for s in args.steps.split(",")]
        steps = steps[-6:] if not args.steps else steps
        fig, axes = plt.subplots(1, len(steps), figsize=(3 * len(steps), 3.2), squeeze=False)
        for ax, s in zip(axes[0], steps):
            if f"step_{s:06d}" not in h5["fields"]:
                sys.exit(f"plot_fields: step {s} not saved; saved steps: {saved_steps(h5)}")
            g = h5[f"fields/step_{s:06d}"]
            if args.field not in g:
                sys.exit(f"plot_fields: step {s} has no field '{args.field}'")
            a = np.asarray(g[args.field])  # array[j, i]: rows along y
            if args.field == "state":
                cmap = ListedColormap(["white", "black", "0.6"])
                ax.imshow(a, origin="lower", cmap=cmap, vmin=-0.5, vmax=2.5,
                          interpolation="nearest")
            else:
                im = ax.imshow(a, origin="lower", cmap="viridis", interpolation="nearest")
                fig.colorbar(im, ax=ax, shrink=0.8)
            ax.set_title(f"step {s}, t = {g.attrs['time']:.3g}", fontsize=9)
            ax.set_xticks([]), ax.set_yticks([])
    fig.tight_layout()
    out = args.out or os.path.join(args.run_dir, f"{args.field}.png")
    fig.savefig(out, dpi=130)
    print(out)


if __name__ == "__main__":
    main()
