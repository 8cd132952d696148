#!/usr/bin/python3
"""result.h5 opened with xarray (engine h5netcdf) as a netCDF user would: the saved fields
over step on x/y coordinates in metres (cell centres), and the time series as one named
variable per column with units.

usage: test_result_xarray.py FRETBEM_BINARY SOURCE_DIR
Exits 77 (ctest's SKIP_RETURN_CODE) without xarray or h5netcdf (Debian: python3-xarray,
python3-h5netcdf). Expected values come from the arguments below (grid, normal force, steps).
"""
import os
import sys
import tempfile

import numpy as np

from support import FZ, LENGTH, NX, NY, STEPS, check, finish, run_small

try:
    import h5netcdf  # noqa: F401  (xarray's engine)
    import xarray as xr
except ImportError as e:
    print("skipped:", e)
    sys.exit(77)

FRETBEM, SOURCE = sys.argv[1], sys.argv[2]
H = LENGTH / NX

with tempfile.TemporaryDirectory() as tmp:
    out = os.path.join(tmp, "run")
    run_small(FRETBEM, SOURCE, out, "pressure,state,slip_x")
    path = os.path.join(out, "result.h5")

    with xr.open_dataset(path, group="series/fields", engine="h5netcdf") as f:
        check(f.pressure.dims == ("step", "y", "x"), f"pressure dims {f.pressure.dims}")
        check(f.pressure.attrs.get("units") == "Pa", "pressure units")
        for axis, n in (("x", NX), ("y", NY)):
            c = f[axis]
            check(c.attrs.get("units") == "m", f"{axis} units")
            check(np.allclose(c.values, (np.arange(n) + 0.5 - n / 2) * H, rtol=0, atol=1e-18),
                  f"{axis}: cell centres")
        # Step 0 (saved without output.fields_every), the turning points at a quarter and
        # three quarters of the cycle, and the last step.
        steps = [0, STEPS // 4, 3 * STEPS // 4, STEPS]
        check(list(f.step.values) == steps, f"saved steps {list(f.step.values)}")
        check(f.time.size == len(steps)
              and np.allclose(f.time.values, np.array(steps) / STEPS, rtol=0, atol=1e-12),
              "time coordinate")
        force = f.pressure.sel(step=0).sum().item() * H * H
        check(abs(force - FZ) <= 1e-9 * FZ, f"step 0 pressure integral {force} N")
        # Labelled selection: the cell nearest the centre carries the peak pressure.
        centre = f.pressure.sel(step=0).sel(x=0, y=0, method="nearest").item()
        check(centre == f.pressure.sel(step=0).max().item(), "peak at the centre")

    with xr.open_dataset(path, group="series/timeseries", engine="h5netcdf") as ts:
        check(list(ts.step.values) == list(range(STEPS + 1)), "time-series steps")
        check("time" in ts.coords, "time is a coordinate")
        units = {"Fz": "N", "Fx": "N", "Ux": "m", "delta": "m", "contact_area": "m2",
                 "dissipation": "J", "kx": "N m-1"}
        for name, unit in units.items():
            check(name in ts.data_vars and ts[name].dims == ("step",), f"variable {name}")
            check(ts[name].attrs.get("units") == unit, f"{name} units")
        check(np.allclose(ts.Fz.values, FZ, rtol=1e-9, atol=0), "Fz is the normal force")
        # The same numbers as the CSV a run writes beside it.
        csv = np.genfromtxt(os.path.join(out, "timeseries.csv"), delimiter=",", names=True)
        check(np.array_equal(ts.Fx.values, csv["Fx"])
              and np.array_equal(ts.Ux.values, csv["Ux"]), "Fx, Ux equal timeseries.csv")

finish()
