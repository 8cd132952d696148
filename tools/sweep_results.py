"""Reading a fretbem sweep for the plot tools: the finished rows of STUDY_DIR/sweep.csv (as
text, the digits the members wrote)."""
import csv
import os

import fretbem_plot as fp


def finished_rows(study_dir, tool):
    """The rows of STUDY_DIR/sweep.csv with status ok; exits naming `tool` when there are none."""
    path = os.path.join(study_dir, "sweep.csv")
    if not os.path.exists(path):
        fp.fail(tool, f"{path}: no sweep.csv (run fretbem sweep first)")
    with open(path) as f:
        rows = [r for r in csv.DictReader(f) if r["status"] == "ok"]
    if not rows:
        fp.fail(tool, f"{path}: no finished member")
    return rows
