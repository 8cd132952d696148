#!/usr/bin/python3
"""result.h5 and checkpoint.h5 describe themselves, read with h5py as a user would.

usage: test_result_h5.py FRETBEM_BINARY SOURCE_DIR
The grid (n = 12 by 16 cells, length 3e-4 m) is set on the command line, so every expected
value below comes from the arguments, not from the program's output.
"""
import os
import subprocess
import sys
import tempfile

import h5py
import numpy as np

from support import check, finish

FRETBEM, SOURCE = sys.argv[1], sys.argv[2]
NX, NY, LENGTH = 16, 12, 3e-4
H = LENGTH / NX


def text(v):
    return v.decode() if isinstance(v, bytes) else str(v)


with tempfile.TemporaryDirectory() as tmp:
    out = os.path.join(tmp, "given_by_out")
    subprocess.run([FRETBEM, "run", os.path.join(SOURCE, "scenarios", "mindlin_cycle.ini"),
                    "--set", f"grid.nx={NX}", "--set", f"grid.ny={NY}",
                    "--set", f"grid.length={LENGTH}", "--set", "load.cycles=1",
                    "--set", "load.steps_per_cycle=8", "--set", "output.dir=not_this_one",
                    "--set", "output.fields=pressure,traction_x,state,slip_x,dissipation,wear",
                    "--set", "output.fields_every=4", "--out", out, "--quiet"], check=True)
    with h5py.File(os.path.join(out, "result.h5"), "r") as f:
        a = f.attrs
        check(text(a["program"]) == "fretbem", "program")
        check(text(a["program_version"]).count(".") == 2, "program_version")
        check(int(a["format_version"]) == 4, "format_version")
        check(list(a["grid_shape"]) == [NY, NX], "grid_shape (y, x)")
        check(np.allclose(a["grid_spacing"], [H, H], rtol=1e-15, atol=0), "grid_spacing")
        # Cell (0, 0) centred at -(n/2 - 1/2) h on each axis: the grid is centred on the origin.
        check(np.allclose(a["grid_origin"], [-(NY / 2 - 0.5) * H, -(NX / 2 - 0.5) * H],
                          rtol=1e-14, atol=0), "grid_origin")
        check(int(a["periodic"]) == 0, "periodic")
        check("[y][x]" in text(a["array_layout"]), "array_layout")
        check(text(a["output_dir"]) == out, "output_dir is --out")
        # /scenario names the folder the run wrote, not the scenario's output.dir.
        scenario = text(f["scenario"][()])
        check(f"dir = {out}" in scenario and "not_this_one" not in scenario, "/scenario dir")
        # Coordinates: the x/y dimension scales hold the cell centres.
        check(np.allclose(f["x"][:], (np.arange(NX) + 0.5 - NX / 2) * H, rtol=0, atol=1e-18),
              "/x centres")
        check(np.allclose(f["y"][:], (np.arange(NY) + 0.5 - NY / 2) * H, rtol=0, atol=1e-18),
              "/y centres")
        check(text(f["x"].attrs["CLASS"]) == "DIMENSION_SCALE", "/x is a dimension scale")
        # Units on every numeric dataset; y and x attached to every 2-D field.
        fields = []
        f.visititems(lambda n, o: fields.append((n, o)) if isinstance(o, h5py.Dataset) else None)
        for name, d in fields:
            if d.dtype.kind in "fiu":
                check("units" in d.attrs, f"units on /{name}")
            if d.ndim == 2 and name != "timeseries":
                check(d.shape == (NY, NX), f"/{name} shape")
                check(np.array_equal(d.dims[0][0][:], f["y"][:])
                      and np.array_equal(d.dims[1][0][:], f["x"][:]), f"/{name} dims")
        steps = sorted(k for k in f["fields"])
        check(len(steps) >= 3, "saved steps")
        g = f["fields"][steps[-1]]
        check(text(g["pressure"].attrs["units"]) == "Pa", "pressure units")
        check(text(g["slip_x"].attrs["units"]) == "m", "slip units")
        check(text(g["dissipation"].attrs["units"]) == "J m-2", "dissipation units")
        st = g["state"]
        check(st.dtype == np.uint8, "state is uint8")
        check(list(st.attrs["flag_values"]) == [0, 1, 2], "state flag_values")
        check(text(st.attrs["flag_meanings"]) == "open stick slip", "state flag_meanings")
        check(set(np.unique(st[:])) <= {0, 1, 2}, "state values")
        # Contact area from the state map equals the time series' (last row).
        ts = f["timeseries"]
        cols = [text(c) for c in ts.attrs["columns"]]
        units = [text(u) for u in ts.attrs["units"]]
        check(len(units) == len(cols), "one unit per column")
        u = dict(zip(cols, units))
        check(u["Fz"] == "N" and u["Ux"] == "m" and u["contact_area"] == "m2"
              and u["dissipation"] == "J" and u["kx"] == "N m-1", "column units")
        check(abs(np.count_nonzero(st[:]) * H * H - ts[-1, cols.index("contact_area")])
              <= 1e-12 * LENGTH**2, "state matches contact_area")
    with h5py.File(os.path.join(out, "checkpoint.h5"), "r") as c:
        check(text(c.attrs["program"]) == "fretbem", "checkpoint program")
        check(np.allclose(c.attrs["grid_spacing"], [H, H], rtol=1e-15, atol=0),
              "checkpoint grid_spacing")
        check(text(c.attrs["output_dir"]) == out, "checkpoint output_dir")

finish()
