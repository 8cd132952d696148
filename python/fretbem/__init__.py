"""fretbem from Python: scenarios, the model stepped one load step at a time, fields as numpy
arrays, the Ciavarella–Jäger shortcut, the Greenwood–Williamson model and closed forms.

    import fretbem
    sc = fretbem.Scenario.from_file("scenarios/mindlin_cycle.ini", ["grid.n=64"])
    stepper = fretbem.Stepper(fretbem.Model(sc))
    rows = [row for row in stepper]          # one dict per step: the timeseries.csv columns
    p = stepper.pressure                      # numpy (ny, nx), Pa
    stepper.cycles[-1]["dissipated_energy"]   # J, the last cycle's row of cycles.csv

See docs/python.md.
"""
from ._fretbem import (InputError, Model, Scenario, SolverError, Stepper,  # noqa: F401
                       __version__, ciavarella_jaeger, cycle_columns, gw, sphere)
from .closed_forms import Contact  # noqa: F401
