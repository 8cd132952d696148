#!/usr/bin/python3
"""Combination sweep: seeded random scenarios over every option a user can combine.

Each case (combo_cases.py: surfaces and height-map files, materials and couplings, friction
laws, ramp/sine/table paths with varying F_z, force/displacement control, wear laws and
integrators, fields, periodic grids, solver options) runs `fretbem run` on a small grid and is
judged:

  refused  exit 2 with one line naming the problem: a combination the program does not take
  pass     exit 0 and every invariant of combo_invariants.py holds on the outputs, and
           - `fretbem check` of the scenario exits 0 (its cost estimate included)
           - `--stop-after K` then `--resume`, or SIGTERM (at once, once the output folder
             exists, i.e. in step 0, or once the time series has k rows) then `--resume`:
             the uninterrupted run's rows and field groups
             (a dirk wear run within its tolerance); a run killed before it could install its
             handler must leave nothing a resume takes (exit 2, one line)
           - an ODE wear run (erk, dirk, arkode; N <= 200): final delta and max worn depth
             within 10 (rtol W + atol) of `wear.integrator = cycle` (combo_invariants.py)
           - load-step keys: a wear run refuses load.substeps > 1 and load.tolerance > 0,
             no other run refuses them, and a constant-load case drawn for it gives the same
             bytes run one step a row (steps_pair)
           - drawn for 15 % of cases, on two MPI ranks: what docs/mpi-grid.md refuses on
             ranks refused (exit 2, one line); the rest, serial and ranks both at solver
             tolerance 1e-12, exit alike and equal to its documented bounds, also stopped
             (`--stop-after`, SIGTERM to one rank) and resumed on the ranks (combo_reruns.py)
           - drawn for 15 % of cases, rerun with `--overwrite` into a copy of the folder:
             clean (the same rows, nothing left aside), stopped by SIGTERM (the finished
             results byte for byte aside until `--resume` finishes it), or failing partway
             (the finished results byte for byte in place)
  fail     anything else: crash (signal), hang (over 60 s of CPU), exit 1 or 3, a message
           that is not one line or shows library text, NaN/inf in an output, a broken invariant

    tools/bench/combination_sweep.py --build build --cases 300 --seed 1 --out DIR
    tools/bench/combination_sweep.py --build build --quick --out DIR   # the ctest subset
    tools/bench/combination_sweep.py --build build --seed 1 --case 17 --out DIR  # one case
    tools/bench/combination_sweep.py --build build --seed 1 --all-mpi --out DIR  # every case
                                                                   # on two MPI ranks too

Writes DIR/cases.csv (one row per case: outcome, problems, the known defect it matches, and
the commands, which run as printed from DIR/cases/NNNN/) and prints a summary; exit 1 when any
case failed. Cases run at most two at a time under `nice`.
"""
import argparse
import concurrent.futures
import csv
import math
import os
import shutil
import signal
import subprocess
import sys
import time

from combo_cases import FULL, QUICK, draw_case
from combo_invariants import final_wear_close, kx_rtol, read_rows, run_invariants, \
    same_field_groups, same_rows
from combo_reruns import MPI_TOLERANCE, error_controlled, files_intact, refused_on_ranks, \
    run_files, same_as_serial, serial_spread
from fretbem_outputs import LIBRARY_TEXT, nonfinite_in_csv, nonfinite_in_h5

# Per fretbem command: the cases take 0.01-20 s of CPU (a coupled dirk wear run at n = 32 took
# 18.5 s), so 60 s of CPU is a hang; the wall limit only guards against a stopped process.
CPU_LIMIT, WALL_LIMIT = 60, 1200
QUICK_SEED, QUICK_CASES = 5, 40
ODE_REFERENCE_MAX_N = 200

# Defects known and open: a failure matching one is labelled so, to tell it from a new one. Each
# entry: (label, test on (case, problem text)); the labels of fixed defects are removed, so that
# their return is labelled NEW. None open (docs/reliability.md, "Combination sweep").
KNOWN_DEFECTS = []


class Run:
    def __init__(self, argv, code, out, err, seconds):
        self.argv, self.code, self.out, self.err, self.seconds = argv, code, out, err, seconds
        self.signal_note = ""  # when a SIGTERM was sent, for the printed command

    def command(self):
        return " ".join(self.argv) + (f" (SIGTERM {self.signal_note})" if self.signal_note
                                      else "")


def cpu_seconds(pid):
    """User + system CPU time of a running process (s), from /proc; 0 once it is gone."""
    try:
        with open(f"/proc/{pid}/stat") as f:
            fields = f.read().rsplit(")", 1)[1].split()
        return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")
    except (OSError, IndexError, ValueError):
        return 0.0


def children(pid):
    """The processes whose parent is `pid` (mpirun's ranks)."""
    kids = []
    for entry in os.listdir("/proc"):
        if entry.isdigit():
            try:
                with open(f"/proc/{entry}/stat") as f:
                    if int(f.read().rsplit(")", 1)[1].split()[1]) == pid:
                        kids.append(int(entry))
            except (OSError, IndexError, ValueError):
                pass
    return kids


def tree_cpu_seconds(pid):
    return cpu_seconds(pid) + sum(cpu_seconds(c) for c in children(pid))


def finish(p, argv, t0, cpu_limit=CPU_LIMIT):
    """Waits for a started run; a run past cpu_limit of CPU (itself and its children: the
    ranks of an mpirun) or WALL_LIMIT of wall time is a hang (CPU, not wall: on the shared
    machine a case gets a tenth of a core at times)."""
    while True:
        try:
            out, err = p.communicate(timeout=0.5)
            return Run(argv, p.returncode, out, err, time.time() - t0)
        except subprocess.TimeoutExpired:
            if tree_cpu_seconds(p.pid) > cpu_limit or time.time() - t0 > WALL_LIMIT:
                for rank in children(p.pid):
                    os.kill(rank, signal.SIGKILL)
                p.kill()
                p.communicate()
                return Run(argv, "timeout", "", "", time.time() - t0)


def start(binary, args, cwd, env=None):
    argv = [binary] + args
    return subprocess.Popen(argv, cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True, env=env), argv, time.time()


def fretbem(binary, args, cwd):
    return finish(*start(binary, args, cwd))


def rows_written(path):
    try:
        with open(path, "rb") as f:
            return max(f.read().count(b"\n") - 1, 0)
    except OSError:
        return 0


def started(series, rows):
    """Whether a run writing `series` has reached `rows` rows (0: made its output folder)."""
    if rows == 0:
        return os.path.isdir(os.path.dirname(series))
    return rows < 0 or rows_written(series) >= rows


def fretbem_terminated(binary, args, cwd, rows):
    """Starts a run and sends SIGTERM once started(rows) holds."""
    p, argv, t0 = start(binary, args, cwd)
    series = os.path.join(cwd, args[args.index("--out") + 1], "timeseries.csv")
    while p.poll() is None and not started(series, rows) and time.time() - t0 < WALL_LIMIT:
        time.sleep(0.005)  # polling the condition, not waiting for time to pass
    if p.poll() is None:
        p.send_signal(signal.SIGTERM)
    run = finish(p, argv, t0)
    run.signal_note = {-1: "at once", 0: "once the output folder exists"}.get(
        rows, f"once timeseries.csv has {rows} rows")
    return run


def exit_problems(run, label, allowed=(0,)):
    """What is wrong with a command's exit and stderr, beyond an allowed code."""
    if run.code == "timeout":
        return [f"hang ({label}): over {CPU_LIMIT} s of CPU or {WALL_LIMIT} s of wall time"]
    problems = []
    if any(t in run.err for t in LIBRARY_TEXT):
        problems.append(f"message ({label}): stderr shows library text: {first_line(run.err)}")
    if run.code in allowed:
        return problems
    if run.code < 0 or run.code > 128:
        problems.append(f"crash ({label}): exit {run.code}: {first_line(run.err)}")
    elif run.code == 2 and not is_refusal(run):
        problems.append(f"message ({label}): exit 2 without one error line: {run.err[:200]!r}")
    elif run.code != 2:
        problems.append(f"exit {run.code} ({label}): {first_line(run.err)}")
    else:
        problems.append(f"exit 2 ({label}): {first_line(run.err)}")
    return problems


def error_lines(err):
    return [line for line in err.splitlines() if "error" in line]


def is_refusal(run):
    return run.code == 2 and len(error_lines(run.err)) == 1 and \
        not any(t in run.err for t in LIBRARY_TEXT)


def first_line(err):
    lines = error_lines(err) or [line for line in err.splitlines() if line.strip()] or [""]
    return lines[-1].strip()[:240]


def kx_documented(case, header, row):
    """kx is finite, or +inf where every contact node of a periodic grid sticks (README, kx:
    a uniform shift of a fully stuck periodic interface meets no compliance)."""
    kx = float(row[header.index("kx")])
    if math.isfinite(kx):
        return True
    stick, contact = (float(row[header.index(c)]) for c in ("stick_area", "contact_area"))
    periodic = str(case.get("grid.periodic")).lower() == "true"
    return periodic and kx == math.inf and contact > 0 and stick == contact


def nonfinite(case, out):
    bad = []
    for name in ("timeseries.csv", "cycles.csv"):
        bad += nonfinite_in_csv(os.path.join(out, name))
    bad += nonfinite_in_h5(os.path.join(out, "result.h5"))
    if str(case.get("solver.stiffness")) in ("every", "true"):
        header, rows = read_rows(os.path.join(out, "timeseries.csv"))
        if "kx" in header and any(not kx_documented(case, header, r) for r in rows):
            bad.append("timeseries.csv:kx (solver.stiffness = every)")
    return [f"nan: {b}" for b in bad[:3]]


def finished_problems(case, cwd, out):
    """Invariants of a run that exited 0, in folder `out` below `cwd`."""
    path = os.path.join(cwd, out)
    return nonfinite(case, path) + run_invariants(case, path)


def implicit_wear(case, plain):
    """dirk, or arkode that chose it (its summary line names the steps)."""
    integ = case.get("wear.integrator")
    return integ == "dirk" or (integ == "arkode" and "implicit" in plain.out)


def compare_resumed(case, cwd, plain, label, out):
    ref, new = os.path.join(cwd, "plain"), os.path.join(cwd, out)
    problems = finished_problems(case, cwd, out)
    if case.is_wear() and implicit_wear(case, plain):
        return problems + final_wear_close(f"resume ({label}, dirk)", case, os.path.join(
            ref, "cycles.csv"), os.path.join(new, "cycles.csv"))
    for name in ("timeseries.csv", "cycles.csv"):
        problems += same_rows(label, name, os.path.join(ref, name), os.path.join(new, name),
                              kx_rtol(case))
    return problems + same_field_groups(label, os.path.join(ref, "result.h5"),
                                        os.path.join(new, "result.h5"))


def resume_and_compare(binary, case, cwd, plain, label, out, runs):
    resume = fretbem(binary, ["run", "--resume", out, "--quiet"], cwd)
    runs.append(resume)
    problems = exit_problems(resume, f"{label} then --resume")
    if problems:
        return problems
    return compare_resumed(case, cwd, plain, label, out)


def stop_and_resume(binary, case, cwd, plain, runs):
    stop = fretbem(binary, ["run", "scenario.ini", "--out", "stop", "--quiet", "--stop-after",
                            str(case.mode_arg)], cwd)
    runs.append(stop)
    problems = exit_problems(stop, "stop-after")
    if problems:
        return problems
    return resume_and_compare(binary, case, cwd, plain, "stop-after", "stop", runs)


def terminate_and_resume(binary, case, cwd, plain, runs):
    term = fretbem_terminated(binary, ["run", "scenario.ini", "--out", "term", "--quiet"], cwd,
                              case.mode_arg)
    runs.append(term)
    label = {-1: "sigterm at once", 0: "sigterm in step 0"}.get(case.mode_arg,
                                                                  "sigterm after k rows")
    if term.code == 0:  # finished before the signal arrived
        return compare_resumed(case, cwd, plain, label, "term")
    if term.code == -signal.SIGTERM:
        # Killed before the handler was installed: nothing may be resumable but a refusal.
        resume = fretbem(binary, ["run", "--resume", "term", "--quiet"], cwd)
        runs.append(resume)
        if is_refusal(resume):
            return []
        if resume.code == 0:
            return compare_resumed(case, cwd, plain, label, "term")
        return exit_problems(resume, f"{label}, killed at start, then --resume")
    problems = exit_problems(term, label, allowed=(143,))
    if problems:
        return problems
    return resume_and_compare(binary, case, cwd, plain, label, "term", runs)


def ode_against_cycle(binary, case, cwd, runs):
    if case.get("wear.integrator") == "cycle" or float(case.get("wear.cycles")) > \
            ODE_REFERENCE_MAX_N:
        return []
    ref = fretbem(binary, ["run", "scenario.ini", "--out", "cycle", "--quiet", "--set",
                           "wear.integrator=cycle"], cwd)
    runs.append(ref)
    problems = exit_problems(ref, "ode-vs-cycle reference")
    if problems:
        return problems
    return final_wear_close("ode-vs-cycle", case, os.path.join(cwd, "cycle", "cycles.csv"),
                            os.path.join(cwd, "plain", "cycles.csv"))


STEP_KEYS = ("load.substeps", "load.tolerance", "load.interpolation")


def step_key_problems(case, plain):
    """A wear run must refuse sub-steps and error control (README); elsewhere the drawn values
    (substeps 1-8, tolerance <= 1e-2, cubic through a normal load of 0.7-1.3 P) are valid."""
    if case.steps_refused() and plain.code == 0:
        return [f"steps: a wear run took load.substeps = {case.get('load.substeps', '-')}, "
                f"load.tolerance = {case.get('load.tolerance', '-')} (README: refused)"]
    if not case.steps_refused() and is_refusal(plain) and \
            any(key in first_line(plain.err) for key in STEP_KEYS):
        return [f"steps: refused a valid load-step key: {first_line(plain.err)}"]
    return []


def steps_pair(binary, case, cwd, runs):
    """A constant-normal-load case with sub-steps or error control against the same case solved
    one step a row: rows at constant normal load are never subdivided (README, load.substeps),
    so both runs make the same solves in the same order and every cell, `convolutions` and
    `kx` included, must be byte for byte the same (StepControl.ConstantNormalLoadIsNeverSubdivided
    asserts the same of one scenario)."""
    if "steps_pair" not in case.notes:
        return []
    keys = ["load.substeps=1", "load.tolerance=0"]
    if case.get("load.path") != "table":
        keys.append("load.interpolation=linear")  # read by tables only
    args = ["run", "scenario.ini", "--out", "whole", "--quiet"]
    for key in keys:
        args += ["--set", key]
    whole = fretbem(binary, args, cwd)
    runs.append(whole)
    problems = exit_problems(whole, "one step a row")
    if problems:
        return problems
    for name in ("timeseries.csv", "cycles.csv"):
        problems += same_rows("one step a row", name, os.path.join(cwd, "whole", name),
                              os.path.join(cwd, "plain", name), rtol=None, what="steps")
    return problems


# --- On two MPI ranks (combo_reruns.py): what docs/mpi-grid.md's table runs on ranks, both
# sides solved to MPI_TOLERANCE, equals the serial run to its documented bounds, also stopped
# and resumed on the ranks; what it refuses is one error line and exit 2. Open MPI's ranks
# poll while they wait for each other, so an MPI run's CPU (the ranks' sum) may be twice the
# serial hang limit.
MPIRUN = ["mpirun", "--allow-run-as-root", "--oversubscribe", "-np", "2"]
MPI_CPU_LIMIT = 2 * CPU_LIMIT


def mpi_banner_removed(run):
    """mpirun's own report of a rank's non-zero exit (blocks between lines of dashes) is not
    fretbem's message: dropped, so that fretbem's lines are judged as serially."""
    kept, inside = [], False
    for line in run.err.splitlines(keepends=True):
        if line.startswith("-----"):
            inside = not inside
        elif not inside:
            kept.append(line)
    run.err = "".join(kept)
    return run


def start_on_ranks(binary, args, cwd):
    """mpirun with Open MPI's session directory in the case's folder: two mpirun started at
    once (two cases, or the test suite beside the sweep) race to create the shared
    session directory ompi.HOST.UID in the temporary root ("mkdir ... File exists", orte_init
    failed)."""
    session = os.path.join(cwd, "ompi")
    os.makedirs(session, exist_ok=True)
    env = dict(os.environ, OMPI_MCA_orte_tmpdir_base=session)
    return start(MPIRUN[0], MPIRUN[1:] + [binary] + args, cwd, env)


def on_ranks(binary, args, cwd):
    return mpi_banner_removed(finish(*start_on_ranks(binary, args, cwd), MPI_CPU_LIMIT))


def terminated_on_ranks(binary, args, cwd, rows):
    """Starts a run on the ranks and sends SIGTERM to one rank once the output folder exists
    and, for rows > 0, timeseries.csv has `rows` rows (a scheduler's signal may reach one
    rank first: docs/mpi-grid.md says the ranks stop after the step in which one has seen it)."""
    p, argv, t0 = start_on_ranks(binary, args, cwd)
    series = os.path.join(cwd, args[args.index("--out") + 1], "timeseries.csv")
    ranks = []
    while p.poll() is None and time.time() - t0 < WALL_LIMIT and \
            not (started(series, max(rows, 0)) and len(ranks := children(p.pid)) == 2):
        time.sleep(0.005)  # polling the condition, not waiting for time to pass
    if p.poll() is None and ranks:
        os.kill(ranks[-1], signal.SIGTERM)
    run = mpi_banner_removed(finish(p, argv, t0, MPI_CPU_LIMIT))
    run.signal_note = f"to one rank once timeseries.csv has {max(rows, 0)} rows"
    return run


class SerialSpread:
    """The serial run's own move at a tenth of MPI_TOLERANCE (combo_reruns.serial_spread), run
    once, when an error-controlled wear run's ranks first part from it beyond the bounds."""

    def __init__(self, binary, case, cwd, runs):
        self.binary, self.case, self.cwd, self.runs, self.spread = binary, case, cwd, runs, None

    def compare(self, label, other):
        serial = os.path.join(self.cwd, "serial")
        problems = same_as_serial(label, self.case, serial, other)
        if not problems or not error_controlled(self.case):
            return problems
        if self.spread is None:
            tighter = fretbem(self.binary, ["run", "scenario.ini", "--out", "serial13", "--quiet",
                                            "--set", f"solver.tolerance={MPI_TOLERANCE / 10:g}"],
                              self.cwd)
            self.runs.append(tighter)
            self.spread = serial_spread(self.case, serial, os.path.join(self.cwd, "serial13")) \
                if tighter.code == 0 else {}
        return same_as_serial(label, self.case, serial, other, self.spread)


def mpi_refusal(binary, case, cwd, why, runs):
    mpi = on_ranks(binary, ["run", "scenario.ini", "--out", "mpi", "--quiet"], cwd)
    runs.append(mpi)
    if is_refusal(mpi):
        return []
    return [f"mpi: {why}: exit {mpi.code} on 2 ranks, not one error line and exit 2: "
            f"{first_line(mpi.err)}"]


def mpi_resumed(binary, case, cwd, plain, out, label, runs, spread):
    """The run folder `out`, stopped on the ranks, resumed on them and compared with the
    uninterrupted serial run (a fresh implicit wear integrator by its final row)."""
    resume = on_ranks(binary, ["run", "--resume", out, "--quiet"], cwd)
    runs.append(resume)
    problems = exit_problems(resume, f"{label} on 2 ranks then --resume")
    if problems:
        return problems
    problems = finished_problems(case, cwd, out)
    ref = os.path.join(cwd, "serial")
    if case.is_wear() and implicit_wear(case, plain):
        return problems + final_wear_close(f"mpi {label} resumed (dirk)", case, os.path.join(
            ref, "cycles.csv"), os.path.join(cwd, out, "cycles.csv"))
    return problems + spread.compare(f"{label} then --resume", os.path.join(cwd, out))


def mpi_interrupted(binary, case, cwd, plain, tight, runs, spread):
    if case.mode == "stop":
        stop = on_ranks(binary, ["run", "scenario.ini", "--out", "mpistop", "--quiet",
                                 "--stop-after", str(case.mode_arg)] + tight, cwd)
        runs.append(stop)
        return exit_problems(stop, "stop-after on 2 ranks") or \
            mpi_resumed(binary, case, cwd, plain, "mpistop", "stop-after", runs, spread)
    term = terminated_on_ranks(binary, ["run", "scenario.ini", "--out", "mpiterm", "--quiet"] +
                               tight, cwd, case.mode_arg)
    runs.append(term)
    if term.code == 0:  # finished before the signal arrived
        return spread.compare("sigterm (finished first)", os.path.join(cwd, "mpiterm"))
    return exit_problems(term, "sigterm on 2 ranks", allowed=(143,)) or \
        mpi_resumed(binary, case, cwd, plain, "mpiterm", "sigterm", runs, spread)


def judge_on_ranks(binary, case, cwd, plain, runs):
    """The MPI checks of a case whose plain run exited 0 or was refused."""
    why = "refused serially" if plain.code != 0 else refused_on_ranks(case)
    if why:
        return mpi_refusal(binary, case, cwd, why, runs)
    tight = ["--set", f"solver.tolerance={MPI_TOLERANCE:g}"]
    serial = fretbem(binary, ["run", "scenario.ini", "--out", "serial", "--quiet"] + tight, cwd)
    mpi = on_ranks(binary, ["run", "scenario.ini", "--out", "mpi", "--quiet"] + tight, cwd)
    runs += [serial, mpi]
    if "timeout" in (serial.code, mpi.code):
        return exit_problems(serial, "serial at 1e-12") + exit_problems(mpi, "2 ranks")
    if mpi.code != serial.code or (serial.code == 2 and not is_refusal(mpi)):
        return [f"mpi: exit {mpi.code} on 2 ranks, {serial.code} serially: "
                f"{first_line(mpi.err)}"] + exit_problems(serial, "serial at 1e-12")
    if serial.code != 0:
        return []
    spread = SerialSpread(binary, case, cwd, runs)
    problems = finished_problems(case, cwd, "mpi") + spread.compare("2 ranks",
                                                                    os.path.join(cwd, "mpi"))
    if not problems and case.mode in ("stop", "sigterm"):
        problems += mpi_interrupted(binary, case, cwd, plain, tight, runs, spread)
    return problems


# --- With --overwrite (combo_reruns.py): the finished run's folder copied, then the same
# command with --overwrite into the copy: "clean" must replace it with the same rows and leave
# nothing aside; "sigterm" (once the new run has set the results aside and written a row) must
# keep them byte for byte in .fretbem-replaced until a --resume finishes the run, which must
# then equal the first run; "fail" (every solve capped at one iteration) must exit with one
# error line and put them back byte for byte (src/io/replaced_results.cpp, tests/test_faults.cpp
# FailedOverwriteKeepsTheResultsItReplaces, StoppedOverwriteKeepsTheResultsUntilItFinishes).
OVER = "over"
REPLACED = ".fretbem-replaced"


def replaced_rows(case, cwd, plain, label, resumed):
    """The overwriting run's results against the first run's (a resumed one as any resumed
    run), nothing left aside."""
    over = os.path.join(cwd, OVER)
    if resumed:
        problems = compare_resumed(case, cwd, plain, label, OVER)
    else:
        problems = finished_problems(case, cwd, OVER) + same_field_groups(
            label, os.path.join(cwd, "plain", "result.h5"), os.path.join(over, "result.h5"))
        for name in ("timeseries.csv", "cycles.csv"):
            problems += same_rows(label, name, os.path.join(cwd, "plain", name),
                                  os.path.join(over, name), kx_rtol(case))
    left = [a for a in (REPLACED, ".fretbem-failed") if os.path.exists(os.path.join(over, a))]
    return problems + ([f"overwrite ({label}): {', '.join(left)} left after it finished"]
                       if left else [])


def overwrite_sigterm(binary, case, cwd, plain, before, args, runs):
    series = os.path.join(cwd, OVER, "timeseries.csv")
    aside = os.path.join(cwd, OVER, REPLACED)
    p, argv, t0 = start(binary, args, cwd)
    while p.poll() is None and time.time() - t0 < WALL_LIMIT and \
            not (os.path.isdir(aside) and rows_written(series) >= 1):
        time.sleep(0.005)  # polling the condition, not waiting for time to pass
    if p.poll() is None:
        p.send_signal(signal.SIGTERM)
    run = finish(p, argv, t0)
    run.signal_note = "once the set-aside folder exists and timeseries.csv has 1 row"
    runs.append(run)
    if run.code == 0:
        return replaced_rows(case, cwd, plain, "overwrite then sigterm (finished first)", False)
    problems = exit_problems(run, "overwrite then sigterm", allowed=(143,))
    problems += files_intact("sigterm", before, aside)
    if problems:
        return problems
    resume = fretbem(binary, ["run", "--resume", OVER, "--quiet"], cwd)
    runs.append(resume)
    return exit_problems(resume, "overwrite then sigterm then --resume") or \
        replaced_rows(case, cwd, plain, "overwrite then sigterm then --resume", True)


def late_iteration_cap(cwd):
    """A solver.max_iterations that the first run's steps before a step k > 0 met and step k
    did not (the last such k: the solves then fail partway, after rows and checkpoints), else
    1 (step 0 fails)."""
    header, rows = read_rows(os.path.join(cwd, "plain", "timeseries.csv"))
    names = [c for c in ("normal_iterations", "tangential_iterations") if c in header]
    most = [max(int(float(r[header.index(c)] or 0)) for c in names) for r in rows]
    cap = 1
    for k in range(1, len(most)):
        if most[k] > max(most[:k]) > 0:
            cap = max(most[:k])
    return cap


def overwrite_failed(binary, case, cwd, before, args, runs):
    """The late cap first; a run it did not stop (the fallbacks re-solve a tangential increment
    that did not converge in sub-steps) is a replacement like any other, whose results the
    cap of 1 iteration, failing at step 0, must then leave in place."""
    for cap in dict.fromkeys([late_iteration_cap(cwd), 1]):
        run = fretbem(binary, args + ["--set", f"solver.max_iterations={cap}"], cwd)
        runs.append(run)
        if run.code != 0:
            break
        problems = finished_problems(case, cwd, OVER)
        if problems:
            return problems
        before = run_files(os.path.join(cwd, OVER))
    if run.code == 0:  # every solve converged in one iteration
        return []
    if len(error_lines(run.err)) != 1 or run.code not in (2, 3):
        return [f"overwrite (fail): exit {run.code}, not one error line and exit 2 or 3: "
                f"{run.err[:200]!r}"]
    return files_intact("fail", before, os.path.join(cwd, OVER))


def judge_overwrite(binary, case, cwd, plain, runs):
    """The --overwrite rerun of a case whose plain run exited 0, into a copy of its folder."""
    shutil.copytree(os.path.join(cwd, "plain"), os.path.join(cwd, OVER))
    before = run_files(os.path.join(cwd, OVER))
    args = ["run", "scenario.ini", "--out", OVER, "--quiet", "--overwrite"]
    if case.overwrite == "sigterm":
        return overwrite_sigterm(binary, case, cwd, plain, before, args, runs)
    if case.overwrite == "fail":
        return overwrite_failed(binary, case, cwd, before, args, runs)
    run = fretbem(binary, args, cwd)
    runs.append(run)
    return exit_problems(run, "overwrite") or replaced_rows(case, cwd, plain, "overwrite", False)


def known_defect(case, problems):
    """The known defects the problems match, and NEW for any problem that matches none."""
    labels = sorted({label for p in problems for label, match in KNOWN_DEFECTS if match(case, p)})
    unmatched = [p for p in problems if not any(m(case, p) for _, m in KNOWN_DEFECTS)]
    return "; ".join(labels + (["NEW"] if unmatched else []))


def write_case(case, cwd):
    if os.path.isdir(cwd):
        shutil.rmtree(cwd)
    os.makedirs(cwd)
    with open(os.path.join(cwd, "scenario.ini"), "w") as f:
        f.write(case.ini())
    for name, data in case.files.items():
        with open(os.path.join(cwd, name), "wb") as f:
            f.write(data)


def check_agrees(binary, cwd, runs):
    """`fretbem check` takes what `run` finished: exit 0, no error line (README, "check": the
    same validation, then a calibrated cost estimate on the run's own solves)."""
    check = fretbem(binary, ["check", "scenario.ini"], cwd)
    runs.append(check)
    if check.code == 0 and not error_lines(check.err):
        return []
    return exit_problems(check, "check") or [f"check: {first_line(check.err)}"]


def judge_case(binary, case, cwd):
    """Runs a case; returns (outcome, problems, runs)."""
    write_case(case, cwd)
    runs = [fretbem(binary, ["run", "scenario.ini", "--out", "plain", "--quiet"], cwd)]
    plain = runs[0]
    problems = step_key_problems(case, plain)
    if is_refusal(plain) and not problems:
        problems = judge_on_ranks(binary, case, cwd, plain, runs) if case.mpi else []
        return ("fail" if problems else "refused"), problems or [first_line(plain.err)], runs
    problems += exit_problems(plain, "run") if not is_refusal(plain) else []
    if not problems:
        problems = finished_problems(case, cwd, "plain") + steps_pair(binary, case, cwd, runs)
        problems += check_agrees(binary, cwd, runs)
        if case.is_wear():
            problems += ode_against_cycle(binary, case, cwd, runs)
        if case.mode == "stop":
            problems += stop_and_resume(binary, case, cwd, plain, runs)
        elif case.mode == "sigterm":
            problems += terminate_and_resume(binary, case, cwd, plain, runs)
        if case.mpi:
            problems += judge_on_ranks(binary, case, cwd, plain, runs)
        if case.overwrite:
            problems += judge_overwrite(binary, case, cwd, plain, runs)
    return ("fail" if problems else "pass"), problems, runs


def sweep_case(binary, seed, index, root, keep, limits, all_mpi=False):
    case = draw_case(seed, index, limits)
    case.mpi = case.mpi or all_mpi
    cwd = os.path.join(root, "cases", f"{index:04d}")
    t0 = time.time()
    outcome, problems, runs = judge_case(binary, case, cwd)
    if outcome != "fail" and not keep:
        for out in ("plain", "stop", "term", "cycle", "whole", "serial", "mpi", "mpistop",
                    "mpiterm", OVER, "ompi"):
            shutil.rmtree(os.path.join(cwd, out), ignore_errors=True)
    failed = outcome == "fail"
    return {"case": index, "mode": case.mode, "mode_arg": case.mode_arg, "outcome": outcome,
            "classes": ", ".join(sorted({p.split(":")[0] for p in problems})) if failed else "",
            "known_defect": known_defect(case, problems) if failed else "",
            "problems": " | ".join(problems), "seconds": f"{time.time() - t0:.2f}",
            "directory": cwd, "commands": " ; ".join(r.command() for r in runs)}


def summary(records):
    counts = {o: sum(r["outcome"] == o for r in records) for o in ("pass", "refused", "fail")}
    lines = [f"cases {len(records)}: passed {counts['pass']}, refused {counts['refused']}, "
             f"failed {counts['fail']}"]
    by_class = {}
    for r in records:
        if r["outcome"] == "fail":
            for c in r["classes"].split(", "):
                by_class.setdefault((c, r["known_defect"]), []).append(r["case"])
    if by_class:
        lines.append("| invariant | known defect | cases |")
        lines.append("|---|---|---|")
        for (c, known), cases in sorted(by_class.items()):
            lines.append(f"| {c} | {known} | {len(cases)}: {' '.join(map(str, cases[:12]))} |")
    return "\n".join(lines)


class Records:
    """cases.csv, one row appended per finished case, so that an interrupted sweep keeps them."""

    def __init__(self, path):
        self.path, self.rows, self.file, self.writer = path, [], None, None

    def add(self, record):
        if self.writer is None:
            self.file = open(self.path, "w", newline="")
            self.writer = csv.DictWriter(self.file, fieldnames=list(record))
            self.writer.writeheader()
        self.writer.writerow(record)
        self.file.flush()
        self.rows.append(record)


def report_failure(r):
    print(f"case {r['case']} FAIL [{r['known_defect']}]: {r['problems'][:300]}\n"
          f"  cd {r['directory']} && {r['commands']}", flush=True)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--build", default="build", help="folder holding the fretbem binary")
    ap.add_argument("--cases", type=int, default=300)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--out", required=True)
    ap.add_argument("--quick", action="store_true",
                    help=f"the ctest subset: seed {QUICK_SEED}, {QUICK_CASES} smaller cases")
    ap.add_argument("--case", type=int, help="run only this case index")
    ap.add_argument("--jobs", type=int, default=2, choices=(1, 2))
    ap.add_argument("--keep", action="store_true", help="keep the outputs of passing cases")
    ap.add_argument("--all-mpi", action="store_true",
                    help="run every case on two MPI ranks too, not the drawn 15 %%")
    a = ap.parse_args()
    binary = os.path.abspath(os.path.join(a.build, "fretbem"))
    seed, count = (QUICK_SEED, QUICK_CASES) if a.quick else (a.seed, a.cases)
    indices = [a.case] if a.case is not None else list(range(count))
    root = os.path.abspath(a.out)
    os.makedirs(root, exist_ok=True)
    os.nice(10)  # the children inherit it: the machine is shared
    records = Records(os.path.join(root, "cases.csv"))
    pool = concurrent.futures.ThreadPoolExecutor(a.jobs)
    limits = QUICK if a.quick else FULL
    futures = [pool.submit(sweep_case, binary, seed, i, root, a.keep, limits, a.all_mpi)
               for i in indices]
    try:
        for f in concurrent.futures.as_completed(futures):
            records.add(f.result())
            if records.rows[-1]["outcome"] == "fail":
                report_failure(records.rows[-1])
    except KeyboardInterrupt:  # SIGINT: summarise the finished cases, start no more
        pool.shutdown(wait=False, cancel_futures=True)
        print(f"interrupted after {len(records.rows)} of {len(indices)} cases")
        print(summary(records.rows), flush=True)
        os._exit(130)  # the running cases' threads would otherwise be joined at exit
    print(f"seed {seed}, binary {binary}")
    print(summary(records.rows))
    return 1 if any(r["outcome"] == "fail" for r in records.rows) else 0


if __name__ == "__main__":
    sys.exit(main())
