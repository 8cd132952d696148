"""Reading a fretbem sweep's results for the plot tools: the finished rows of DIR/sweep.csv and
a member's resolved scenario (the /scenario text of its result.h5)."""
import configparser
import csv
import os
import sys

import h5py


def finished_rows(study_dir, tool):
    """The rows of STUDY_DIR/sweep.csv with status ok; exits naming `tool` when there are none."""
    path = os.path.join(study_dir, "sweep.csv")
    if not os.path.exists(path):
        sys.exit(f"{tool}: {path}: no sweep.csv (run fretbem sweep first)")
    with open(path) as f:
        rows = [r for r in csv.DictReader(f) if r["status"] == "ok"]
    if not rows:
        sys.exit(f"{tool}: {path}: no finished member")
    return rows


def resolved_scenario(member_dir):
    """The member's resolved scenario (every key) as a ConfigParser."""
    with h5py.File(os.path.join(member_dir, "result.h5"), "r") as f:
        text = f["scenario"][()].decode()
    cp = configparser.ConfigParser(inline_comment_prefixes=("#",))
    cp.read_string(text)
    return cp
