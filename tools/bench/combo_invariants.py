"""Invariants of a finished fretbem run, checked from its output files (combination_sweep.py).

Each check returns a list of problems, each a short string "invariant: detail"; empty is a
pass. Tolerances and why:
- |F_t| <= mu_max F_z: the traction is projected node by node onto |tau_i| <= mu_i p_i, so the
  sum obeys it up to what the solves leave: 10 x solver.tolerance (the normal residual makes
  F_z; the coupled alternation stops at solver.coupling_tolerance) plus round-off.
- dissipation non-decreasing: each node adds g |s| >= 0 (README, "Dissipation and the loop"),
  so a decrease beyond round-off (1e-12 of the total) is wrong.
- energy law: the worn depth of a step is alpha |tau . s| with the same s and tau the
  dissipation sums (docs/wear.md, "Laws"), so volume = alpha x dissipation to round-off (1e-9
  relative: sums of ~n^2 terms in another order).
- ODE against `cycle`, and a dirk run resumed (fresh integrator) against its uninterrupted run:
  the max worn depth W within 10 (rtol W + atol), the integrators' error control (docs/wear.md,
  "Integrators": atol = rtol x the unworn indentation unless wear.atol is given) with the
  factor 10 of tools/bench/wear_sweep.py's reference cases for the global error; delta within
  that plus 10 solver tolerances of delta (its normal solve).
- step_error (timeseries.csv and cycles.csv): finite and >= 0, as an estimate of a relative
  error; exactly 0 where nothing is estimated: load.tolerance 0 or absent, a normal load that
  never changes (rows at constant normal load are never subdivided), wear runs (README,
  step_error).
- resumed = uninterrupted: byte-identical CSV cells except `convolutions` (a work counter) and
  `kx` within 1e-7 relative (docs/reliability.md, "the uninterrupted run's rows"); with
  solver.fft_precision = float within 2 (tol + 2^-23), tol = max(solver.tolerance, 1e-6):
  each of the two stiffness solves (different warm starts) stops within its tolerance of the
  converged k_x (the contract Stiffness.EnergyStopKeepsKxWithinTheTolerance holds; the stop
  aims at kShare = 0.1 of it, src/contact/stiffness.cpp, but float round-off in the energy's
  increments, ~2^-23 of it, is within a decade of that aim and the extrapolated remainder can
  miss it: 0.23 tol measured against a double solve to 1e-12, seed 51 case 33 stopped after
  3 steps at tol 1e-5), whose tolerance float FFTs raise to at least kFloatFftMinTolerance =
  1e-6, and the converged k_x itself carries the float operator's round-off, one
  single-precision epsilon 2^-23 = 1.2e-7 relative (measured 1e-7 rms, docs/performance.md);
  the two differ by at most twice the sum, 2.2e-6 at 1e-6.
"""
import csv
import math
import os

KX_RTOL = 1e-7
KX_STOP_SHARE = 0.1  # StiffnessSolver's kShare
FLOAT_EPSILON = 2.0 ** -23
FLOAT_FFT_MIN_TOLERANCE = 1e-6  # kFloatFftMinTolerance
ROUND_OFF = 1e-12
ENERGY_LAW_RTOL = 1e-9
WORK_COUNTERS = ("convolutions",)
KX_COLUMNS = ("kx", "kx_at_max", "kx_at_min")  # cycles.csv takes its kx_at_* from kx


def read_rows(path):
    """(header, rows as lists of strings); ([], []) when the file is missing."""
    if not os.path.exists(path):
        return [], []
    with open(path, newline="") as f:
        lines = list(csv.reader(f))
    return (lines[0], lines[1:]) if lines else ([], [])


def column(header, rows, name):
    i = header.index(name)
    return [float(r[i]) for r in rows]


def friction_bound(case, header, rows):
    if "Fz" not in header:
        return []
    fz, fx, fy = (column(header, rows, c) for c in ("Fz", "Fx", "Fy"))
    tol = 10 * float(case.get("solver.tolerance", 1e-8)) + ROUND_OFF
    if case.get("solver.coupling") == "coupled":
        tol += 10 * float(case.get("solver.coupling_tolerance", 1e-6))
    mu = case.mu_max()
    worst = max(((math.hypot(x, y) / (mu * z), i) for i, (z, x, y) in enumerate(zip(fz, fx, fy))
                 if z > 0), default=(0.0, 0))
    if worst[0] > 1 + tol:
        return [f"friction: |F_t| = {worst[0]:.9g} mu_max F_z at row {worst[1]} "
                f"(mu_max {mu:g}, tolerance {tol:.1e})"]
    return []


def dissipation_monotone(header, rows):
    d = column(header, rows, "dissipation")
    if not d:
        return []
    slack = ROUND_OFF * max(abs(v) for v in d)
    for i in range(1, len(d)):
        if d[i] < d[i - 1] - slack:
            return [f"dissipation: decreases at row {i} by {d[i - 1] - d[i]:.3g} J "
                    f"({(d[i - 1] - d[i]) / max(d[-1], 1e-300):.2g} of the total)"]
    return []


def energy_law_rows(case, header, rows):
    """Cycle mode: timeseries `wear_volume` = alpha x `dissipation`, both cumulative from 0."""
    alpha = float(case.get("wear.coefficient"))
    d, w = column(header, rows, "dissipation"), column(header, rows, "wear_volume")
    for i, (di, wi) in enumerate(zip(d, w)):
        if abs(wi - alpha * di) > ENERGY_LAW_RTOL * max(alpha * d[-1], 1e-300):
            return [f"energy-law: wear_volume {wi:.9g} != alpha x dissipation {alpha * di:.9g} "
                    f"at timeseries row {i}"]
    return []


def wear_shares(case, header, rows):
    s = float(case.get("wear.indenter_share", 1))
    total, ind, half = (column(header, rows, c) for c in
                        ("wear_volume", "wear_volume_indenter", "wear_volume_half_space"))
    for i, (t, a, b) in enumerate(zip(total, ind, half)):
        if abs(a - s * t) > ROUND_OFF * abs(t) or abs(b - (1 - s) * t) > ROUND_OFF * abs(t):
            return [f"wear-shares: row {i}: indenter {a:g}, half-space {b:g} of {t:g} (s = {s})"]
    return []


def energy_law_cycles(case, header, rows):
    """Cycle mode: each cycle adds alpha x its energy to the worn volume of the next row."""
    alpha = float(case.get("wear.coefficient"))
    e, v = column(header, rows, "energy_per_cycle"), column(header, rows, "wear_volume")
    scale = max(max(v, default=0.0), 1e-300)
    for i in range(len(v) - 1):
        if abs(v[i + 1] - v[i] - alpha * e[i]) > ENERGY_LAW_RTOL * scale:
            return [f"energy-law: cycles.csv row {i + 1}: volume gained {v[i + 1] - v[i]:.9g} "
                    f"!= alpha x energy {alpha * e[i]:.9g}"]
    return []


def step_error_valid(case, name, header, rows):
    if "step_error" not in header:
        return []
    estimated = float(case.get("load.tolerance", 0)) > 0 and case.varying_normal() \
        and not case.is_wear()
    for i, e in enumerate(column(header, rows, "step_error")):
        if not (math.isfinite(e) and e >= 0) or (e != 0 and not estimated):
            return [f"step-error: {name} row {i}: step_error {e:g} (load.tolerance "
                    f"{case.get('load.tolerance', 0)}, normal load "
                    f"{'varying' if case.varying_normal() else 'constant'})"]
    return []


def run_invariants(case, out):
    """Every invariant a run that exited 0 must satisfy."""
    problems = []
    header, rows = read_rows(os.path.join(out, "timeseries.csv"))
    if not rows:
        return ["outputs: timeseries.csv has no rows"]
    problems += friction_bound(case, header, rows)
    problems += dissipation_monotone(header, rows)
    problems += step_error_valid(case, "timeseries.csv", header, rows)
    ch, cr = read_rows(os.path.join(out, "cycles.csv"))
    problems += step_error_valid(case, "cycles.csv", ch, cr)
    if case.is_wear():
        problems += wear_shares(case, ch, cr)
        if case.get("wear.law") == "energy" and case.get("wear.integrator") == "cycle":
            problems += energy_law_rows(case, header, rows)
            problems += energy_law_cycles(case, ch, cr)
    return problems


def kx_rtol(case):
    """Relative difference allowed between a resumed and an uninterrupted run's kx (docstring
    above: max(1e-7, 2 kShare tol) in double, or float FFTs' bound, 2 (tol + 2^-23))."""
    if case.get("solver.fft_precision") != "float":
        tol = float(case.get("solver.tolerance", 1e-8))
        return max(KX_RTOL, 2 * KX_STOP_SHARE * tol)
    tol = max(float(case.get("solver.tolerance", FLOAT_FFT_MIN_TOLERANCE)),
              FLOAT_FFT_MIN_TOLERANCE)
    return 2 * (tol + FLOAT_EPSILON)


def cells_equal(name, a, b, rtol=KX_RTOL):
    """Resumed against uninterrupted; rtol None: every cell byte for byte."""
    if a == b:
        return True
    if rtol is None:
        return False
    if name in WORK_COUNTERS:
        return True
    if name not in KX_COLUMNS:
        return False
    x, y = float(a), float(b)
    if math.isnan(x) and math.isnan(y):
        return True
    return abs(x - y) <= rtol * max(abs(x), abs(y))


def same_rows(label, file, reference, resumed, rtol=KX_RTOL, what="resume"):
    (h1, r1), (h2, r2) = read_rows(reference), read_rows(resumed)
    if h1 != h2:
        return [f"{what} ({label}): {file} header differs"]
    if len(r1) != len(r2):
        return [f"{what} ({label}): {file} has {len(r2)} rows, the reference {len(r1)}"]
    for i, (a, b) in enumerate(zip(r1, r2)):
        for name, x, y in zip(h1, a, b):
            if not cells_equal(name, x, y, rtol):
                return [f"{what} ({label}): {file} row {i} column {name}: {y} vs reference {x}"]
    return []


def wear_tolerances(case, rows):
    """(rtol, atol in m, the normal solve's relative tolerance) of a wear run: atol defaults to
    rtol x the unworn indentation delta0, the N = 0 row (docs/wear.md, "Integrators")."""
    rtol = float(case.get("wear.rtol", 1e-3))
    delta0 = float(rows[0]["delta"])
    atol = float(case.get("wear.atol", rtol * delta0))
    return rtol, atol, float(case.get("solver.tolerance", 1e-8))


def final_wear_close(label, case, reference, other):
    """Final max worn depth W within 10 (rtol W + atol) of the reference's, and delta within
    that plus 10 solver tolerances of delta (the normal solve's own error)."""
    (h1, r1), (h2, r2) = read_rows(reference), read_rows(other)
    if not r1 or not r2:
        return [f"{label}: cycles.csv missing or empty"]
    a, b = dict(zip(h1, r1[-1])), dict(zip(h2, r2[-1]))
    if float(a["N"]) != float(b["N"]):
        return [f"{label}: ended at N = {b['N']}, reference at {a['N']}"]
    rtol, atol, tol = wear_tolerances(case, [dict(zip(h1, r)) for r in r1])
    wear_allowed = 10 * (rtol * float(a["max_worn_depth"]) + atol)
    allowed = {"max_worn_depth": wear_allowed,
               "delta": wear_allowed + 10 * tol * float(a["delta"])}
    for name, limit in allowed.items():
        d = abs(float(a[name]) - float(b[name]))
        if d > limit:
            return [f"{label}: final {name} {b[name]} vs {a[name]}: {d:.3g} m apart, "
                    f"allowed {limit:.3g} m (10 (rtol W + atol), rtol {rtol:g}, atol {atol:.3g} m)"]
    return []


def field_groups(path):
    """{group/dataset: array} of result.h5's /fields and /wear, {} when unreadable."""
    import h5py
    out = {}
    try:
        with h5py.File(path, "r") as f:
            for top in ("fields", "wear"):
                if top in f:
                    f[top].visititems(lambda n, o: out.__setitem__(f"{top}/{n}", o[()])
                                      if isinstance(o, h5py.Dataset) else None)
    except OSError as e:
        out["unreadable"] = str(e)
    return out


def same_field_groups(label, reference, resumed):
    import numpy as np
    a, b = field_groups(reference), field_groups(resumed)
    if set(a) != set(b):
        missing, extra = sorted(set(a) - set(b))[:2], sorted(set(b) - set(a))[:2]
        return [f"resume ({label}): result.h5 field groups differ "
                f"(missing {missing}, extra {extra})"]
    for name in a:
        if not np.array_equal(a[name], b[name]):
            return [f"resume ({label}): result.h5 {name} differs"]
    return []
