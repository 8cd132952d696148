#!/usr/bin/python3
"""Energy dissipated per steady cycle against the tangential amplitude Q*/(mu P), log-log, from a
fretbem sweep over load.amplitude (sweep.csv): a sphere next to Mindlin-Deresiewicz, or rough
surfaces (one curve per value of the other varied keys, mean over surface.seed with the
seeds' range as a band, a slope-3 guide).

usage: tools/plot_energy_per_cycle.py STUDY_DIR [STUDY_DIR ...] [--out energy_per_cycle.png]

Sphere studies: several study directories draw together (the force-controlled amplitudes of
study_energy_per_cycle.ini and the displacement-controlled members past full sliding of
study_energy_per_cycle_gross_slip.ini): panel (a) W against Q*/mu P, panel (b) W against the
displacement amplitude D/u* with the gross-slip line 4 mu P (D - 4u*/5) beyond D = u*.

Closed form (fretbem_plot.Contact.md_energy, Johnson eq. 7.60): W(q) = (24/5) mu P u*
[1 - (1-q)^(5/3) - (5q/6)(1 + (1-q)^(2/3))] ~ (4/27) mu P u* q^3, u* = mu delta E*/G*. The slip
annulus is a (1 - (1-q)^(1/3)) wide: the grid resolves it with at least two cells only where
that exceeds 2h; points below are drawn hollow. Prints one line per member (sphere) or per
group and amplitude (rough). Writes PNG and PDF.
"""
import argparse
import os

import numpy as np
import fretbem_plot as fp
from sweep_results import finished_rows

TOOL = "plot_energy_per_cycle"


def sphere_members(rows, study_dirs):
    """Per member: control, Q*/mu P (force control), D (the cycle's Ux amplitude), W, and the
    slip-ring width in cells on the member's own grid (a study may refine it per member)."""
    out = []
    for r in rows:
        scn = fp.read_scenario(os.path.join(r["_study"], r["dir"]))
        c = fp.Contact(scn)
        n = fp.number(scn, "grid.nx") or fp.number(scn, "grid.n")  # a refined member: nx, ny
        a, h = c.hertz_radius(), fp.number(scn, "grid.length") / n
        force = scn.get("load.control", "force") == "force"
        q = float(scn["load.amplitude"]) if force else np.nan
        ring = a * (1 - (1 - q) ** (1 / 3)) / h if force else np.nan
        if r.get("ring_cells_predicted"):
            ring = float(r["ring_cells_predicted"])
        out.append(dict(force=force, q=q, D=float(r["Ux_amplitude"]),
                        W=float(r["dissipated_energy"]), ring=ring, a_h=a / h))
    return out


def plot_sphere(rows, scn, out, study_dirs):
    """(a) W against Q*/mu P (force control) next to Mindlin–Deresiewicz; (b) W against the
    displacement amplitude D/u* of every member, with the gross-slip line 4 mu P (D - 4u*/5)
    past full sliding (displacement control)."""
    c = fp.Contact(scn)
    muP = c.mu * c.P
    ustar = c.sliding_shift(c.hertz_indentation())
    m = sphere_members(rows, study_dirs)
    print("control, q, D/u*, W (J), W closed form (J), ratio, slip annulus (cells), a/h")
    for x in sorted(m, key=lambda x: x["D"]):
        Wc = c.md_energy(x["q"] * muP) if x["force"] else c.displacement_energy(x["D"])
        print(f"{'force' if x['force'] else 'displacement'}, {x['q']:.4g}, {x['D'] / ustar:.4g}, "
              f"{x['W']:.6g}, {Wc:.6g}, {x['W'] / Wc:.5f}, {x['ring']:.2f}, {x['a_h']:.0f}")
    fig, axs = fp.figure(ncols=2, width=4.2, height=3.2)
    force = [x for x in m if x["force"]]
    ax = axs[0, 0]
    if force:
        q = np.array([x["q"] for x in force])
        qq = np.logspace(np.log10(min(q.min(), 0.01)), np.log10(0.999), 200)
        ax.loglog(qq, c.md_energy(qq * muP) / (muP * ustar), "k-", lw=1,
                  label="Mindlin–Deresiewicz")
        ax.loglog(qq, 4 / 27 * qq**3, "k:", lw=1, label="slope 3: (4/27) q³")
        draw_members(ax, force, "q", muP * ustar)
    ax.set_xlabel("Q*/(μP)")
    ax.set_ylabel("W / (μP u*)")
    ax.set_title("force control" if force else "force control (no member)")
    if force:
        ax.legend()
    ax = axs[0, 1]
    D = np.array([x["D"] for x in m]) / ustar
    dd = np.logspace(np.log10(min(D.min(), 0.01)), np.log10(max(D.max(), 2) * 1.2), 300)
    ax.loglog(dd, c.displacement_energy(dd * ustar) / (muP * ustar), "k-", lw=1,
              label="Mindlin–Deresiewicz / gross slip 4(D/u* − 4/5)")
    ax.axvline(1, color="0.6", lw=0.8, ls="--")
    for x in m:
        x["d"] = x["D"] / ustar
    draw_members(ax, m, "d", muP * ustar)
    ax.set_xlabel("displacement amplitude D/u*")
    ax.set_title("all members (u*: full-sliding shift)")
    ax.legend()
    fig.suptitle(f"energy per cycle, sphere, a/h = {min(x['a_h'] for x in m):.0f}"
                 f"–{max(x['a_h'] for x in m):.0f}")
    fp.save(fig, out)


def draw_members(ax, members, xkey, scale):
    """Members as dots: filled where the slip ring spans two cells or more (or nothing is left
    to resolve: gross slip), hollow below."""
    x = np.array([m[xkey] for m in members])
    W = np.array([m["W"] for m in members]) / scale
    ok = np.array([not (m["ring"] < 2) for m in members])
    ax.loglog(x[ok], W[ok], "o", color="C0", label="fretbem (annulus ≥ 2 cells)")
    if (~ok).any():
        ax.loglog(x[~ok], W[~ok], "o", mfc="none", color="C0", label="fretbem (annulus < 2 cells)")


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
    fig, axs = fp.figure(width=4.2, height=3.2)
    ax = axs[0, 0]
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
    ax.set_title("energy per cycle, rough surfaces (mean, range over seeds)")
    ax.legend()
    fp.save(fig, out)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("study_dir", nargs="+")
    ap.add_argument("--out", default=None)
    args = ap.parse_args()
    rows = []
    for d in args.study_dir:
        for r in finished_rows(d, TOOL):
            r["_study"] = d
            rows.append(r)
    scn = fp.read_scenario(os.path.join(rows[0]["_study"], rows[0]["dir"]))
    out = args.out or os.path.join(args.study_dir[0], "energy_per_cycle.png")
    if fp.Contact(scn).hertz_ok:
        plot_sphere(rows, scn, out, args.study_dir)
    else:
        if any("load.amplitude" not in r for r in rows):
            fp.fail(TOOL, "load.amplitude is not varied in this study")
        plot_rough(rows, out)


if __name__ == "__main__":
    fp.guarded(main, TOOL)
