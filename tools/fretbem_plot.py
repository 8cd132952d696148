"""What every fretbem plot tool shares: reading a run's outputs, the closed forms users compare
against, and one figure style saved as PNG and PDF.

Imported by tools/plot_*.py (they run with Debian's /usr/bin/python3, python3-numpy, -h5py,
-matplotlib). Units are SI unless a name says otherwise.
"""
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

# Readable at publication size: a single-column figure is ~3.3 in wide, so 9-10 pt text.
STYLE = {
    "font.size": 9,
    "axes.labelsize": 9,
    "axes.titlesize": 9,
    "legend.fontsize": 8,
    "xtick.labelsize": 8,
    "ytick.labelsize": 8,
    "axes.grid": True,
    "grid.alpha": 0.3,
    "savefig.dpi": 200,
    "savefig.bbox": "tight",
    "pdf.fonttype": 42,  # embed TrueType: editable text in journals' pipelines
}


def fail(tool, message):
    sys.exit(f"{tool}: {message}")


def figure(ncols=1, nrows=1, width=3.4, height=2.8, **kw):
    """A figure of ncols x nrows panels, each width x height inches (per panel, not the whole
    figure), in the shared style."""
    plt.rcParams.update(STYLE)
    return plt.subplots(nrows, ncols, figsize=(width * ncols, height * nrows), squeeze=False,
                        layout="constrained", **kw)


def panel_grid(count, most_columns=3):
    """(ncols, nrows) for `count` panels: rows of at most `most_columns`, so that many panels
    wrap into a grid instead of a strip (six maps in one row are 3500 x 600 px)."""
    ncols = max(1, min(count, most_columns))
    return ncols, -(-count // ncols)


def save(fig, out):
    """Saves the figure as OUT (PNG) and beside it as PDF; prints both paths."""
    root, ext = os.path.splitext(out)
    png = out if ext.lower() == ".png" else root + ".png"
    pdf = root + ".pdf"
    fig.savefig(png)
    fig.savefig(pdf)
    plt.close(fig)
    print(png)
    print(pdf)


def count(N):
    """A cycle count as fretbem prints it (core/format.hpp format_count): an integer when it is
    one up to round-off (64 ulps), else 6 significant digits (a label, not data)."""
    N = float(N)
    r = round(N)
    if math.isfinite(N) and abs(r) < 2**53 and abs(N - r) <= 64 * math.ulp(N):
        return str(int(r))
    return f"{N:.6g}"


class Columns(dict):
    """The columns of a CSV file; a missing one ends the tool naming the file and the column
    (a foreign or damaged file gave a KeyError traceback)."""

    def __init__(self, columns, path, tool):
        super().__init__(columns)
        self.path, self.tool = path, tool

    def __missing__(self, key):
        fail(self.tool, f"{self.path}: no column '{key}' (not the file this tool reads?)")


def read_csv(path, tool):
    """A fretbem CSV (header row, numbers, `nan` allowed; `#` comment lines skipped) as a dict
    of numpy columns. A torn or foreign file ends the tool with one line naming file and line."""
    if not os.path.exists(path):
        fail(tool, f"{path}: not found")
    with open(path, errors="replace") as f:
        lines = [(n, ln) for n, ln in enumerate(f, 1)
                 if ln.strip() and not ln.lstrip().startswith("#")]
    if not lines:
        fail(tool, f"{path}: empty")
    names = [c.strip() for c in lines[0][1].split(",")]
    rows = []
    for n, ln in lines[1:]:
        cells = ln.split(",")
        if len(cells) != len(names):
            fail(tool, f"{path}:{n}: {len(cells)} values for {len(names)} columns (a torn "
                       "or foreign file)")
        try:
            rows.append([float(c) if c.strip() else math.nan for c in cells])
        except ValueError:
            fail(tool, f"{path}:{n}: not a number in '{ln.strip()[:60]}' (a torn file?)")
    data = np.array(rows, dtype=float).reshape(len(rows), len(names))
    return Columns({n: data[:, i] for i, n in enumerate(names)}, path, tool)


def open_h5(path, tool):
    """h5py.File(path) for reading; a missing or damaged file ends the tool in one line."""
    import h5py

    if not os.path.exists(path):
        fail(tool, f"{path}: not found")
    try:
        return h5py.File(path, "r")
    except OSError as e:
        fail(tool, f"{path}: cannot be read as HDF5 ({e})")


def guarded(main, tool):
    """Runs a tool's main: what a damaged run folder still raises past the checks above (a
    group missing from result.h5, an unreadable file) ends in one line, not a traceback."""
    try:
        main()
    except (KeyError, OSError, ValueError, IndexError) as e:
        fail(tool, f"cannot read the run's files: {type(e).__name__}: {e}")


def read_scenario(run_dir):
    """The resolved scenario of a run as {'section.key': 'value'}: from result.h5 when h5py
    can read it, else from the run's INI copy if present; {} when neither exists."""
    text = None
    h5 = os.path.join(run_dir, "result.h5")
    if os.path.exists(h5):
        try:
            import h5py

            with h5py.File(h5, "r") as f:
                t = f["scenario"][()]
                text = t.decode() if isinstance(t, bytes) else str(t)
        except (ImportError, OSError, KeyError):
            text = None
    if text is None:
        return {}
    out, section = {}, None
    for line in text.splitlines():
        line = line.split("#")[0].strip()
        if line.startswith("["):
            section = line.strip("[] ")
        elif "=" in line and section:
            k, v = (s.strip() for s in line.split("=", 1))
            out[f"{section}.{k}"] = v
    return out


def number(scn, key, default=None):
    v = scn.get(key)
    try:
        return float(v) if v is not None else default
    except ValueError:
        return default


def _closed_forms():
    """python/fretbem/closed_forms.py, loaded by path: the plot tools need no compiled module."""
    import importlib.util

    here = os.path.dirname(os.path.abspath(__file__))
    path = os.path.join(here, "..", "python", "fretbem", "closed_forms.py")
    spec = importlib.util.spec_from_file_location("fretbem_closed_forms", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


_cf = _closed_forms()


class Contact(_cf.Contact):
    """The closed forms of a run, its effective moduli read from the resolved scenario."""

    def __init__(self, scn):
        def body(e, n):
            return (number(scn, e), number(scn, n)) if scn.get(e) else None

        super().__init__(body("material.E", "material.nu"), body("material.E2", "material.nu2"),
                         mu=number(scn, "material.mu", 0.3),
                         radius=number(scn, "surface.radius")
                         if scn.get("surface.type") == "sphere" else None,
                         normal_force=number(scn, "load.normal_force"))


def run_labels(args, tool):
    """Legend labels of args.run_dirs: --labels (one per run) or the folders' names."""
    labels = args.labels.split(",") if args.labels else \
        [os.path.basename(os.path.normpath(d)) for d in args.run_dirs]
    if len(labels) != len(args.run_dirs):
        fail(tool, "--labels: give one label per run")
    return labels


def cycle_of_steps(time):
    """Cycle index of each step: a step belongs to the cycle holding (t_{k-1}, t_k]
    (row 0, t = 0, to cycle 0)."""
    return np.maximum(np.ceil(np.asarray(time) - 1e-12) - 1, 0).astype(int)
