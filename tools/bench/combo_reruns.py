"""Checks of the combination sweep's reruns (combination_sweep.py): a case on two MPI ranks
against the serial run, and a run folder's files before and after an --overwrite rerun.

Two ranks against one process (docs/mpi-grid.md, "Tests" and "What differs from the serial
run"): both solved to MPI_TOLERANCE = 1e-12, every column of timeseries.csv and cycles.csv and
every numeric dataset of result.h5 within 1e-10 of its largest magnitude, or of the scale a
value that can be round-off needs (component_scale; a step's field: the field's largest over the
saved steps, dataset_scale), 1e-10 / wear.rtol for the error-controlled
wear integrators (relative_bound): the ranks change the order of the sums, so the iterates
part by round-off and each stops within the solver tolerance of the exact increment; 1e-12
makes the 1e-10 a statement about the distribution.
Excepted, as documented: `convolutions` (no sparse direct sums on a distributed grid) and the
`*_iterations`, `*_residual` columns (where each run's stopping test passed); k_x columns
within 2e-9, twice the stiffness solve's tolerance floor of 1e-9. What the table of
docs/mpi-grid.md refuses on ranks (refused_on_ranks) must be one error line and exit 2.
"""
import math
import os
import re

from combo_invariants import read_rows

MPI_TOLERANCE = 1e-12
MPI_RELATIVE = 1e-10
MPI_KX_RELATIVE = 2 * 1e-9
# result.h5's run description (text) and the compound copy of the time series, whose columns
# /series/timeseries/NAME are compared one by one.
H5_SKIPPED = ("timeseries", "run_id", "scenario")


def refused_on_ranks(case):
    """Why docs/mpi-grid.md's table refuses the case on two ranks, or None when it runs."""
    if case.get("friction.law", "constant") != "constant":
        return "friction.law"
    if case.get("solver.monotone") == "shortcut":
        return "solver.monotone = shortcut"
    if case.get("solver.fft_precision") == "float":
        return "solver.fft_precision = float"
    if case.get("solver.coupling") == "coupled" and not identical_bodies(case):
        return "solver.coupling = coupled with cross terms"
    return None


def identical_bodies(case):
    """Two bodies of the same E and nu: no normal-tangential cross term (Dundurs beta = 0)."""
    return "material.E2" in case.keys and \
        (case.get("material.E2"), case.get("material.nu2")) == \
        (case.get("material.E"), case.get("material.nu"))


def relative_bound(case):
    """MPI_RELATIVE, divided by wear.rtol for the error-controlled wear integrators (erk, dirk,
    arkode): their error estimate is the difference of two solutions that agree to ~rtol, so
    it carries the round-off between the two sides divided by rtol, and so do the step sizes
    the controller takes from it (and the Jacobian-free Newton-Krylov variant differences the
    wear map over a step of ~rtol relative, docs/mpi-grid.md). Measured: the rows' N parted by
    6.4e-9 at rtol 1e-3 on seed 51 case 37 (dirk, Krylov, n = 24) and by 4.2e-10 on seed 53
    case 30 (dirk, frozen slip, N = 1000)."""
    if error_controlled(case):
        return MPI_RELATIVE / float(case.get("wear.rtol", 1e-3))
    return MPI_RELATIVE


def error_controlled(case):
    """A wear run of erk, dirk or arkode: its steps follow its error estimate."""
    return case.is_wear() and case.get("wear.integrator") != "cycle"


def solver_cost(name):
    return name == "convolutions" or name.endswith("_iterations") or name.endswith("_residual")


def relative_difference(a, b, scale=0.0):
    """Largest |a - b| over the largest of |a| and `scale`; NaN agrees with NaN only (inf: they
    disagree)."""
    if len(a) != len(b):
        return math.inf
    diff = 0.0
    for x, y in zip(a, b):
        if math.isnan(x) or math.isnan(y):
            if math.isnan(x) != math.isnan(y):
                return math.inf
            continue
        if math.isinf(x) or math.isinf(y):
            if x != y:
                return math.inf
            continue
        scale, diff = max(scale, abs(x)), max(diff, abs(x - y))
    return 0.0 if diff == 0.0 else diff / scale


def partner(name):
    """The other in-plane component of a vector column or field (Fx and Fy, slip_x and
    slip_y), or None."""
    if name.endswith(("x", "y")) and name[-2:-1] in ("F", "U", "_"):
        return name[:-1] + ("y" if name.endswith("x") else "x")
    return None


# Energies of the loop and the forces and shifts that bound them: a fully stuck contact
# dissipates nothing and its loop area is round-off (1e-20 J against F U = 1e-7 J on seed 51
# case 12, a flat punch), so they are measured against the loop's box, F_amplitude U_amplitude.
LOOP_ENERGY = {"loop_area": ("Fx_amplitude", "Ux_amplitude"),
               "dissipated_energy": ("Fx_amplitude", "Ux_amplitude"),
               "dissipation": ("Fx", "Ux")}


# Shares of F_z: their error is that of the forces they sum over F_z, so they are measured
# against 1 (an edge share of 3.6e-3 parted by 2.4e-9 of F_z under the Krylov bound on seed 51
# case 37, 6.8e-7 of its own largest value).
SHARES = ("edge_load_share",)


def largest(values):
    return max((abs(v) for v in values or [] if math.isfinite(v)), default=0.0)


def energy_scale(values, name):
    """F U of the loop for a loop energy (LOOP_ENERGY), 0 otherwise."""
    head, _, tail = name.rpartition("/")
    pair = LOOP_ENERGY.get(tail)
    if not pair:
        return 0.0
    prefix = head + "/" if head else ""
    force, shift = (values.get(prefix + c) for c in pair)
    force_y, shift_y = (values.get(prefix + c[:1] + "y" + c[2:]) for c in pair)
    return max(largest(force), largest(force_y)) * max(largest(shift), largest(shift_y))


def component_scale(values, name):
    """The largest magnitude of the vector a component belongs to, of the loop's box for a loop
    energy (energy_scale), 1 for a share of F_z: a component that is round-off
    (Fy of a load along x, coupled into y by the Cerruti terms: 1e-20 N against Fx's 0.1 N on
    seed 53 case 59) is measured against the vector, not against its own round-off."""
    if name.rpartition("/")[2] in SHARES:
        return 1.0
    other = values.get(partner(name)) if partner(name) else None
    return max(largest(other), energy_scale(values, name))


def number(cell):
    try:
        return float(cell)
    except ValueError:
        return math.nan


def compared(where, name, a, b, scale, relative):
    """[(what, difference, bound)] of one column or dataset; [] for a solver cost."""
    if solver_cost(name):
        return []
    bound = max(MPI_KX_RELATIVE, relative) if name.startswith("kx") else relative
    return [(f"{where} {name}", relative_difference(a, b, scale), bound)]


def table_columns(header, rows):
    return {c: [number(r[i]) for r in rows] for i, c in enumerate(header)}


# Columns of x alone whose vector has no y column beside them: the stick zone's share of F_x
# and cycles.csv's amplitudes, round-off for a load along y (Fx_stick 9e-13 N against F_y =
# 12.7 N on seed 59 case 18, 0.36 to 1.7 of itself apart on two ranks; Fx_amplitude 7.9e-16 N,
# Ux_amplitude 4.6e-20 m): measured against the run's largest force or shift (run_scales).
X_ALONE = {"Fx_stick": "F", "Fx_amplitude": "F", "Ux_amplitude": "U"}


def run_scales(timeseries):
    """{column: scale} from a run's timeseries.csv, both in-plane components: the largest force
    or shift for X_ALONE, and F U of the whole run for a loop energy (LOOP_ENERGY) of
    cycles.csv, whose Fx_amplitude and Ux_amplitude are round-off for a load along y
    (loop_area, the loop of F along y, -6e-23 J against F U = 6.4e-8 J and Fx U_x = 2.4e-40 J
    on seed 55 case 57)."""
    values = table_columns(*read_rows(timeseries))
    vector = {c: max(largest(values.get(c + "x")), largest(values.get(c + "y"))) for c in "FU"}
    out = {name: vector[c] for name, c in X_ALONE.items()}
    out.update({name: vector["F"] * vector["U"] for name in LOOP_ENERGY})
    return out


def table_differences(name, serial, other, relative, run):
    """(problems of shape, [(what, difference, bound)]) of two runs' `name` (a CSV file);
    `run`: the serial run's scales (run_scales)."""
    (h1, r1), (h2, r2) = read_rows(serial), read_rows(other)
    if h1 != h2:
        return [f"{name} header differs"], []
    if len(r1) != len(r2):
        return [f"{name} has {len(r2)} rows, the serial run {len(r1)}"], []
    a, b = table_columns(h1, r1), table_columns(h1, r2)
    out = []
    for col in h1:
        scale = max(component_scale(a, col), run.get(col, 0.0))
        out += compared(f"{name} column", col, a[col], b[col], scale, relative)
    return [], out


def numeric_datasets(path):
    """{path: flat list of floats} of every numeric dataset of an HDF5 file, {} unreadable."""
    import h5py
    import numpy as np
    out = {}

    def visit(name, obj):
        if isinstance(obj, h5py.Dataset) and obj.dtype.kind in "iuf" and \
                name not in H5_SKIPPED:
            out[name] = np.asarray(obj[()], dtype=float).ravel().tolist()
    try:
        with h5py.File(path, "r") as f:
            f.visititems(visit)
    except OSError:
        return {}
    return out


# A field of one saved step's group, fields/step_NNNNNN/NAME or wear/snapshot_NNNNNN/NAME: a row
# of that field's history, as a cell of timeseries.csv is of its column (series/fields/NAME and
# series/wear/NAME hold the same values and are measured against their largest magnitude over
# the saved steps). Against the step's own largest value a field that is still small carries
# the whole run's solver share: the per-node dissipation at the first step of a slip ring
# (8 nodes, slip ~1/70 of the shift) missed its converged value (solver.tolerance = 1e-14) by
# 1.3e-10 of itself serially and on two ranks alike at 1e-12, and the two parted by 3e-13 at
# 1e-14 (seed 58 case 42).
SAVED_STEP = re.compile(r"(fields/step_|wear/snapshot_)\d+/")


def history_of(name):
    """The name of a saved step's dataset with its step left out (SAVED_STEP), else None."""
    return SAVED_STEP.sub(r"\1*/", name) if SAVED_STEP.search(name) else None


def field_history(values):
    """{history_of(name): largest magnitude of that field over every saved step}."""
    out = {}
    for name, v in values.items():
        key = history_of(name)
        if key:
            out[key] = max(out.get(key, 0.0), largest(v))
    return out


def dataset_scale(values, history, run, name):
    """component_scale, the run's scale (run_scales) for a copy of a CSV column, and for a
    saved step's field its history's (and its partner's) largest."""
    head, _, tail = name.rpartition("/")
    scale = component_scale(values, name)
    if head in ("series/timeseries", "series/cycles"):
        scale = max(scale, run.get(tail, 0.0))
    key = history_of(name)
    if key:
        other = partner(key)
        scale = max(scale, history.get(key, 0.0), history.get(other, 0.0) if other else 0.0)
    return scale


def dataset_differences(serial, other, relative, run):
    """(problems of shape, [(what, difference, bound)]) of two runs' result.h5."""
    a, b = numeric_datasets(serial), numeric_datasets(other)
    if set(a) != set(b):
        missing, extra = sorted(set(a) - set(b))[:2], sorted(set(b) - set(a))[:2]
        return [f"result.h5 datasets differ (missing {missing}, extra {extra})"], []
    history = field_history(a)
    out = []
    for name in sorted(a):
        out += compared(f"result.h5 {name}", name.rsplit("/", 1)[-1], a[name], b[name],
                        dataset_scale(a, history, run, name), relative)
    return [], out


def differences(case, serial, other):
    """(problems of shape, [(what, difference, bound)]) of run folder `other` against the
    serial run folder `serial`: every file, column and dataset at the module's bounds."""
    relative = relative_bound(case)
    run = run_scales(os.path.join(serial, "timeseries.csv"))
    shape, out = [], []
    for name in ("timeseries.csv", "cycles.csv"):
        s, d = table_differences(name, os.path.join(serial, name), os.path.join(other, name),
                                 relative, run)
        shape, out = shape + s, out + d
    s, d = dataset_differences(os.path.join(serial, "result.h5"),
                               os.path.join(other, "result.h5"), relative, run)
    return shape + s, out + d


# The serial run's own move when its solver tolerance is tightened tenfold, column by column
# (serial_spread): an error-controlled wear run whose wear map changes by a node's stick or
# slip takes other steps for a perturbation of round-off size, and its rows then part by the
# integrator's error, not by 1e-10 / wear.rtol. Seed 57 case 11 (arkode, wear.rtol = 1e-2,
# a worn sphere under indentation control whose stick zone shrinks node by node from N = 146):
# the serial run at 1e-13 parts from the one at 1e-12 by 2.2e-4 (N) and 1.3e-5 (F_z), the
# two ranks from the serial run at 1e-12 by 0.65 to 1.6 of that in every column and saved
# field's history, by up to 35 times it in one wear snapshot (hence by history). The ranks
# are held to SPREAD_FACTOR times that move: two perturbations of round-off size part the
# steps alike, and the factor is the room between two such draws.
SPREAD_FACTOR = 10


def serial_spread(case, serial, tighter):
    """{what: difference} of the serial run at a tenth of its tolerance (`tighter`), a saved
    step's field by its history's largest (history_of, as its scale), or {} when the two
    differ in shape (rows, datasets)."""
    shape, out = differences(case, serial, tighter)
    spread = {}
    for what, d, _ in out:
        key = history_of(what) or what
        spread[key] = max(spread.get(key, 0.0), d)
    return {} if shape else spread


def same_as_serial(label, case, serial, mpi, spread=None):
    """The run folder `mpi` against the serial run folder `serial` (the module's bounds, or
    SPREAD_FACTOR times the serial run's own move, `spread`, where that is larger)."""
    shape, out = differences(case, serial, mpi)
    problems = [f"mpi ({label}): {p}" for p in shape]
    for what, d, bound in out:
        allowed = max(bound, SPREAD_FACTOR * (spread or {}).get(history_of(what) or what, 0.0))
        if d > allowed:
            problems.append(f"mpi ({label}): {what}: {d:.3g} of its largest magnitude apart "
                            f"(allowed {allowed:g})")
    return problems[:6]


# The files fretbem keeps beside a run's results while it replaces them (src/io/
# replaced_results.cpp) and its lock: not results.
ASIDE = (".fretbem-failed", ".fretbem-replaced", ".fretbem-replacing", ".fretbem-restoring",
         ".fretbem.lock")


def run_files(folder):
    """{name: bytes} of a run folder's results (ASIDE left out); {} when it is missing."""
    out = {}
    if not os.path.isdir(folder):
        return out
    for name in sorted(os.listdir(folder)):
        path = os.path.join(folder, name)
        if name not in ASIDE and os.path.isfile(path):
            with open(path, "rb") as f:
                out[name] = f.read()
    return out


def files_intact(label, before, folder):
    """The finished results `before` ({name: bytes}) are the files of `folder`, byte for byte."""
    after = run_files(folder)
    if after == before:
        return []
    changed = sorted(n for n in set(before) | set(after) if before.get(n) != after.get(n))
    return [f"overwrite ({label}): {os.path.basename(folder)} differs from the finished "
            f"results in {', '.join(changed[:4])}"]
