#!/usr/bin/python3
"""Hysteresis loops F_x - U_x of one or more fretbem runs, with the energy per cycle and, for a
sphere under a sine at constant normal force, the Mindlin–Deresiewicz loop and energy
(Johnson, Contact Mechanics, §7.5): at the force amplitude under force control, between the
shift amplitudes under displacement control (gross slip past the full-sliding shift).

usage: tools/plot_hysteresis.py RUN_DIR [RUN_DIR ...] [--out FILE.png] [--normalise]
                                [--cycles all|last|0,2] [--labels A,B]

One run: one colour per cycle (a colour bar instead of a legend past 8 cycles). Several runs:
one colour per run, overlaid. --normalise plots F_x/(mu F_z) against U_x/U*, with the
full-sliding shift U* = mu delta E*/G* (delta from the run's first row, E* and G* from its
scenario in result.h5). The energy per cycle is the nodal dissipation of the last complete
cycle (DIR/cycles.csv), not the cumulative dissipation, which includes the first loading.
Writes FILE.png and FILE.pdf (default: hysteresis.png in the first run's folder).
"""
import argparse
import os

import numpy as np

import fretbem_plot as fp

TOOL = "plot_hysteresis"


def steady_energy(run_dir):
    """Energy per cycle of the last complete cycle, or None."""
    path = os.path.join(run_dir, "cycles.csv")
    if not os.path.exists(path):
        return None
    cyc = fp.read_csv(path, TOOL)
    if "dissipated_energy" not in cyc or len(cyc["dissipated_energy"]) == 0:
        return None
    full = cyc["steps"] == np.max(cyc["steps"])
    return float(cyc["dissipated_energy"][full][-1])


def md_reference(scn, contact):
    """The closed-form loop of a sphere under a sine at constant normal force, else None:
    (U, F, energy per cycle, label). Force control: Mindlin–Deresiewicz at Q*; displacement
    control: the Masing loop between -+D, in gross slip past the full-sliding shift u*."""
    if not (contact.hertz_ok and scn.get("load.path") == "sine"):
        return None
    if scn.get("load.control", "force") == "force":
        amp = fp.number(scn, "load.amplitude")
        if amp is None:
            return None
        q_star = amp * contact.mu * contact.P
        u, f = contact.md_loop(q_star)
        return u, f, contact.md_energy(q_star), "Mindlin–Deresiewicz"
    D = fp.number(scn, "load.displacement_amplitude")
    if not D:
        return None
    u, f = contact.displacement_loop(D)
    gross = D >= contact.sliding_shift(contact.hertz_indentation())
    return u, f, float(contact.displacement_energy(D)), \
        "gross slip (Mindlin–Deresiewicz)" if gross else "Mindlin–Deresiewicz"


def choose_cycles(spec, available):
    if spec in (None, "all"):
        return list(available)
    if spec == "last":
        return [available[-1]]
    wanted = [int(c) for c in spec.split(",")]
    missing = [c for c in wanted if c not in available]
    if missing:
        fp.fail(TOOL, f"--cycles: no cycle {missing[0]}; the run has cycles "
                      f"{available[0]}..{available[-1]}")
    return wanted


def scales(ts, scn, contact, normalise):
    """(x scale, y scale, x label, y label) for U_x and F_x."""
    if not normalise:
        return 1e9, 1.0, "tangential shift $U_x$ (nm)", "tangential force $F_x$ (N)"
    if contact is None:
        fp.fail(TOOL, "--normalise needs the run's scenario (result.h5 with h5py)")
    u_star = contact.sliding_shift(ts["delta"][0])
    return (1 / u_star, 1 / (contact.mu * ts["Fz"][0]), r"$U_x / U^*$",
            r"$F_x / \mu F_z$")


def plot_run(ax, run_dir, label, colour, args, many):
    ts = fp.read_csv(os.path.join(run_dir, "timeseries.csv"), TOOL)
    if os.path.exists(os.path.join(run_dir, "cycles.csv")) and "N" in fp.read_csv(
            os.path.join(run_dir, "cycles.csv"), TOOL):
        fp.fail(TOOL, f"{run_dir} is a wear run: its time series holds turning points of "
                      "simulated cycles, not loops; use tools/plot_wear.py")
    scn = fp.read_scenario(run_dir)
    contact = fp.Contact(scn) if scn else None
    sx, sy, xl, yl = scales(ts, scn, contact, args.normalise)
    cyc = fp.cycle_of_steps(ts["time"])
    chosen = choose_cycles(args.cycles, list(np.unique(cyc)))
    cmap = fp.plt.get_cmap("viridis")
    for n, c in enumerate(chosen):
        idx = np.nonzero(cyc == c)[0]
        idx = np.concatenate(([max(idx[0] - 1, 0)], idx))  # from the cycle's start point
        col = colour if many else cmap(n / max(1, len(chosen) - 1))
        lab = (label if n == len(chosen) - 1 else None) if many else \
            (f"cycle {c}" if len(chosen) <= 8 else None)
        ax.plot(ts["Ux"][idx] * sx, ts["Fx"][idx] * sy, lw=1.0, color=col, label=lab)
    energy = steady_energy(run_dir)
    ref = md_reference(scn, contact) if contact else None
    if ref is not None:
        u, f, _, name = ref
        ax.plot(u * sx, f * sy, "k--", lw=0.8, label=name if not many or colour == "C0" else None)
    return xl, yl, energy, (ref[2] if ref else None), len(chosen)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("run_dirs", nargs="+", metavar="RUN_DIR")
    ap.add_argument("--out", default=None, help="image file (PNG; a PDF is written beside it)")
    ap.add_argument("--normalise", action="store_true",
                    help="F_x/(mu F_z) against U_x/U*, U* = mu delta E*/G*")
    ap.add_argument("--cycles", default=None, help="all (default), last, or a list such as 0,2")
    ap.add_argument("--labels", default=None, help="legend labels of the runs, comma separated")
    args = ap.parse_args()
    labels = fp.run_labels(args, TOOL)
    many = len(args.run_dirs) > 1
    fig, axes = fp.figure(width=4.2, height=3.3)
    ax = axes[0][0]
    notes = []
    for k, (d, lab) in enumerate(zip(args.run_dirs, labels)):
        xl, yl, energy, md, ncyc = plot_run(ax, d, lab, f"C{k}", args, many)
        if energy is not None:
            text = f"{lab}: {energy:.4g} J/cycle"
            if md:
                text += f" (MD {md:.4g} J, {100 * (energy / md - 1):+.2f} %)"
            notes.append(text)
    ax.set_xlabel(xl)
    ax.set_ylabel(yl)
    if not many and ncyc > 8:
        sm = fp.plt.cm.ScalarMappable(cmap="viridis", norm=fp.plt.Normalize(0, ncyc - 1))
        fig.colorbar(sm, ax=ax, label="cycle")
    ax.legend(loc="upper left", frameon=False)
    if notes:
        ax.set_title("\n".join(notes), fontsize=8)
    out = args.out or os.path.join(args.run_dirs[0], "hysteresis.png")
    fp.save(fig, out)


if __name__ == "__main__":
    fp.guarded(main, TOOL)
