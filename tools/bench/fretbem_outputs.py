"""What every fretbem output must be, checked from the files alone (shared by the bench tools).

LIBRARY_TEXT: fragments of library or runtime text that must never reach a user's stderr
(README, "Exit status": one line naming the file, key or value).
nonfinite_in_csv / nonfinite_in_h5 / scan_outputs: NaN or inf in an output, except where the
README documents it (kx on rows solver.stiffness skips; aggregate bins no member covers).
"""
import glob
import os

LIBRARY_TEXT = ("std::", "basic_", "bad_alloc", "filesystem error", "terminate", "Assertion",
                "Traceback", "what():", "HDF5-DIAG", "Segmentation")


def nonfinite_in_csv(path):
    """Cells that are nan/inf, except kx (README: nan where solver.stiffness skips it)."""
    bad = []
    try:
        with open(path, encoding="utf-8", errors="replace") as f:
            header = f.readline().strip().split(",")
            for ln, line in enumerate(f, start=2):
                row = dict(zip(header, line.strip().split(",")))
                if row.get("members") == "0":  # documented: no member covers the bin
                    continue
                for col, cell in row.items():
                    c = cell.strip().lower()
                    if c in ("nan", "-nan", "inf", "-inf", "+inf", "infinity"):
                        if col in ("kx", "final_kx", "kx_at_max", "kx_at_min"):
                            continue
                        if col.endswith("_ci95"):  # documented: < 2 members cover the bin
                            continue
                        bad.append(f"{os.path.basename(path)}:{ln}:{col}={cell}")
    except OSError:
        pass
    return bad


def nonfinite_in_h5(path):
    try:
        import h5py
        import numpy as np
    except ImportError:
        return []
    bad = []
    try:
        with h5py.File(path, "r") as f:
            def visit(name, obj):
                if isinstance(obj, h5py.Dataset) and obj.dtype.kind == "f":
                    a = obj[()]
                    if name == "series/timeseries/kx":  # the kx column as a variable
                        return
                    if name.endswith("timeseries"):  # kx column documented nan
                        cols = list(f["timeseries"].attrs.get("columns", []))
                        cols = [c.decode() if isinstance(c, bytes) else c for c in cols]
                        if "kx" in cols:
                            a = np.delete(np.atleast_2d(a), cols.index("kx"), axis=1)
                    if not np.all(np.isfinite(a)):
                        bad.append(f"{os.path.basename(path)}:/{name}")
            f.visititems(visit)
    except Exception:  # a torn or foreign file is not this check's business
        pass
    return bad


def scan_outputs(root):
    bad = []
    for p in glob.glob(os.path.join(root, "**", "*.csv"), recursive=True):
        if os.path.dirname(p) != root:  # the case's own input files sit at the top
            bad += nonfinite_in_csv(p)
    for p in glob.glob(os.path.join(root, "**", "*.h5"), recursive=True):
        if not p.endswith("checkpoint.h5"):
            bad += nonfinite_in_h5(p)
    return bad
