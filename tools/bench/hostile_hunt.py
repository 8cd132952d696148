#!/usr/bin/env python3
"""Hostile-user hunt: what a careless or hostile user types, case by case.

Runs what a careless or hostile user types at every surface of fretbem — sweeps, ensembles,
wear keys, load tables, height-map files, output options, `check`, the Python module and the
plot tools — on small grids (n = 16-32), and flags, per case:

  crash    a signal (exit > 128 other than 130/143 when a signal was asked for), a Python
           interpreter killed by one, or a traceback from a tool
  hang     the case's time limit passed
  message  a failure whose stderr is not one line naming something (library text, empty)
  nan      NaN or inf in any CSV cell (kx excepted where README documents it) or HDF5 dataset
  expect   an exit code other than the one the case expects

    nice -n 10 tools/bench/hostile_hunt.py build [--filter TEXT] [--list] [--keep DIR]

Prints one line per case and a count per area; exit 1 when any case is flagged. The cases
that found defects are kept as regression tests (tests/bad_inputs/, test_sweep.cpp, ...);
this script is the record of what was tried (docs/reliability.md, "Hostile-user hunt").
"""
import argparse
import os
import shutil
import signal
import struct
import subprocess
import sys
import tempfile
import time

from fretbem_outputs import LIBRARY_TEXT, scan_outputs

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", ".."))
SC = os.path.join(ROOT, "scenarios")
SMALL = ["--set", "grid.n=16"]
MINDLIN = os.path.join(SC, "mindlin_cycle.ini")
ROUGH = os.path.join(SC, "rough_monotone.ini")
WEAR = os.path.join(SC, "fretting_wear.ini")
GROSS = os.path.join(SC, "gross_slip_wear.ini")
VARYING = os.path.join(SC, "varying_normal.ini")
PY = "/usr/bin/python3"


class Case:
    def __init__(self, area, name, argv, expect=None, timeout=60, setup=None, env=None,
                 signal_after=None, allow_warn=False, out=None, cwd=None):
        self.area, self.name, self.argv, self.expect = area, name, argv, expect
        self.timeout, self.setup, self.env = timeout, setup, env
        self.signal_after, self.allow_warn, self.out, self.cwd = signal_after, allow_warn, out, cwd


def judge(case, code, err, elapsed, work):
    flags = []
    if case.area == "mpi":  # mpirun's own report of a non-zero rank is not fretbem's text
        err = "\n".join(l for l in err.splitlines() if "fretbem" in l)
    if code == "timeout":
        return ["hang"]
    sig_ok = case.signal_after is not None and code in (130, 143)
    if (code < 0 or code > 128) and not sig_ok:
        flags.append(f"crash(exit {code})")
    if case.expect is not None and code != case.expect:
        flags.append(f"expect(exit {code}, wanted {case.expect})")
    lines = [l for l in err.splitlines() if l.strip()]
    if any(t in err for t in LIBRARY_TEXT):
        flags.append("message(library text)")
    if code not in (0, 130, 143) and not case.name.startswith("tool:"):
        errors = [l for l in lines if "error" in l]
        if not errors:
            flags.append("message(no error line)")
    flags += [f"nan({b})" for b in scan_outputs(work)[:3]]
    return flags


def run_case(case, work):
    if case.setup:
        case.setup(work)
    argv = [a.replace("@W", work) if isinstance(a, str) else a for a in case.argv]
    env = dict(os.environ)
    if case.env:
        env.update({k: v.replace("@W", work) for k, v in case.env.items()})
    t0 = time.time()
    try:
        p = subprocess.Popen(argv, stdout=subprocess.PIPE, stderr=subprocess.PIPE, env=env,
                             cwd=case.cwd.replace("@W", work) if case.cwd else work,
                             start_new_session=True)
        if case.signal_after is not None:
            time.sleep(case.signal_after)
            p.send_signal(signal.SIGTERM)
        out, err = p.communicate(timeout=case.timeout)
        code = p.returncode
    except subprocess.TimeoutExpired:
        os.killpg(p.pid, signal.SIGKILL)
        p.communicate()
        return "timeout", "", time.time() - t0
    return code, err.decode("utf-8", "replace"), time.time() - t0


# ---------------------------------------------------------------- helpers for inputs


def write(path, text, mode="w"):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, mode) as f:
        f.write(text)


def study(work, name, vary, extra="", base=MINDLIN, sets=("grid.n=16", "load.cycles=1",
                                                           "load.steps_per_cycle=8")):
    text = f"[study]\nscenario = {base}\n" + "".join(f"set = {s}\n" for s in sets) + extra + \
        "\n[vary]\n" + vary + "\n"
    write(os.path.join(work, name), text)


def npy_bytes(shape, values, dtype="<f8", header_shape=None, fortran=False):
    hs = header_shape if header_shape is not None else shape
    shape_txt = "(" + ", ".join(str(s) for s in hs) + ("," if len(hs) == 1 else "") + ")"
    hdr = "{'descr': '%s', 'fortran_order': %s, 'shape': %s, }" % (dtype, fortran, shape_txt)
    hdr = hdr + " " * (63 - (len(hdr) + 10) % 64) + "\n"
    fmt = {"<f8": "d", "<f4": "f", "<i4": "i", ">f8": "d"}[dtype]
    order = ">" if dtype.startswith(">") else "<"
    body = struct.pack(order + fmt * len(values), *values)
    return b"\x93NUMPY\x01\x00" + struct.pack("<H", len(hdr)) + hdr.encode() + body


def flat_text(n, value="0"):
    return "\n".join(" ".join([value] * n) for _ in range(n)) + "\n"


# ---------------------------------------------------------------- the cases

def cases(build):
    fb = os.path.join(build, "fretbem")
    out = []

    def add(area, name, argv, **kw):
        out.append(Case(area, name, argv, **kw))

    run = [fb, "run"]
    rq = ["--quiet", "--out", "@W/out"]

    # ---- ensemble
    ens = [fb, "ensemble", ROUGH, "--set", "grid.n=16", "--set", "load.steps=3", "--quiet"]
    for name, args, exp in [
        ("one member", ["--hurst", "0.5", "--seeds", "1"], 0),
        ("hurst empty", ["--hurst", ""], 2), ("hurst trailing comma", ["--hurst", "0.5,"], 2),
        ("hurst commas", ["--hurst", ",,,"], 2), ("hurst 0", ["--hurst", "0"], 2),
        ("hurst 1.5", ["--hurst", "1.5"], 2), ("hurst nan", ["--hurst", "nan"], 2),
        ("hurst inf", ["--hurst", "inf"], 2), ("hurst -0.5", ["--hurst", "-0.5"], 2),
        ("hurst 1e-300", ["--hurst", "1e-300", "--seeds", "1"], 0),
        ("hurst spaces", ["--hurst", " 0.5 , 0.7 ", "--seeds", "1"], 0),
        ("hurst duplicate", ["--hurst", "0.5,0.50"], 2),
        ("hurst semicolon", ["--hurst", "0.5;0.7"], 2),
        ("seeds 0", ["--hurst", "0.5", "--seeds", "0"], 2),
        ("seeds -1", ["--hurst", "0.5", "--seeds", "-1"], 2),
        ("seeds 1e9", ["--hurst", "0.5", "--seeds", "1e9"], 2),
        ("seeds 2.5", ["--hurst", "0.5", "--seeds", "2.5"], 2),
        ("seeds huge", ["--hurst", "0.5", "--seeds", "2147483647"], 2),
        ("jobs 0", ["--hurst", "0.5", "--seeds", "1", "--jobs", "0"], 0),
        ("jobs -3", ["--hurst", "0.5", "--jobs", "-3"], 2),
        ("jobs 100000", ["--hurst", "0.5", "--seeds", "2", "--jobs", "100000"], 0),
        ("bins 0", ["--hurst", "0.5", "--bins", "0"], 2),
        ("bins -1", ["--hurst", "0.5", "--bins", "-1"], 2),
        ("bins 1", ["--hurst", "0.5", "--seeds", "2", "--bins", "1"], 0),
        ("bins abc", ["--hurst", "0.5", "--bins", "abc"], 2),
        ("bins 1e8", ["--hurst", "0.5", "--bins", "100000000"], 2),
        ("hurst twice", ["--hurst", "0.5", "--hurst", "0.7"], 2),
        ("no hurst", ["--seeds", "1"], 2),
        ("sphere scenario", ["--hurst", "0.5", "--seeds", "2", "--set", "surface.type=sphere",
                             "--set", "surface.radius=0.01"], 2),
        ("stiffness none", ["--hurst", "0.5", "--seeds", "2", "--set", "solver.stiffness=none"],
         2),
        ("stiffness turning", ["--hurst", "0.5", "--seeds", "2", "--set",
                               "solver.stiffness=turning"], 2),
        ("path none", ["--hurst", "0.5", "--seeds", "2", "--set", "load.path=none"], 2),
        ("force ramp", ["--hurst", "0.5", "--seeds", "2", "--set", "load.control=force",
                        "--set", "load.amplitude=0.5"], 0),
        ("bad set", ["--hurst", "0.5", "--set", "load.bogus=1"], 2),
    ]:
        add("ensemble", name, ens + args + ["--out", "@W/e"], expect=exp)
    add("ensemble", "out is a file", ens + ["--hurst", "0.5", "--seeds", "1", "--out", "@W/f"],
        expect=2, setup=lambda w: write(os.path.join(w, "f"), "x"))
    add("ensemble", "out empty string", ens + ["--hurst", "0.5", "--out", ""], expect=2)
    # A re-run into an ensemble's folder continues it (docs/paper-reproduction.md).
    add("ensemble", "out holds an ensemble",
        ens + ["--hurst", "0.5", "--seeds", "1", "--out", "@W/e"], expect=0,
        setup=lambda w: write(os.path.join(w, "e", "members.csv"), "x\n"))
    add("ensemble", "missing scenario", [fb, "ensemble", "/nonexistent.ini", "--hurst", "0.5"],
        expect=2)
    add("ensemble", "scenario is a folder", [fb, "ensemble", SC, "--hurst", "0.5"], expect=2)
    add("ensemble", "SIGTERM mid-run",
        [fb, "ensemble", ROUGH, "--set", "grid.n=32", "--set", "load.steps=40", "--hurst",
         "0.5,0.7", "--seeds", "3", "--jobs", "1", "--quiet", "--out", "@W/e"],
        expect=143, signal_after=1.5)

    # ---- sweep
    sw = lambda f, *a: [fb, "sweep", f"@W/{f}", "--quiet", "--out", "@W/sw", *a]
    for name, vary, extra, exp in [
        ("two amplitudes", "load.amplitude = 0.3, 0.5", "", 0),
        ("linear count 0", "load.amplitude = linear(0.1,0.5,0)", "", 2),
        ("linear count nan", "load.amplitude = linear(0.1,0.5,nan)", "", 2),
        ("linear count 2.5", "load.amplitude = linear(0.1,0.5,2.5)", "", 2),
        ("linear unclosed", "load.amplitude = linear(0.1,0.5,2", "", 2),
        ("linear 4 args", "load.amplitude = linear(0.1,0.5,2,3)", "", 2),
        ("log zero end", "load.amplitude = log(0,0.5,2)", "", 2),
        ("log negative", "load.amplitude = log(-1,0.5,2)", "", 2),
        ("linear equal ends", "load.amplitude = linear(0.1,0.1,3)", "", 2),
        ("empty in list", "load.amplitude = 0.3,,0.5", "", 2),
        ("no values", "load.amplitude =", "", 2),
        ("empty key", "= 0.3", "", 2),
        ("unknown key", "bogus.key = 1,2", "", 2),
        ("denormal", "load.amplitude = 1e-320, 0.3", "", 2),
        ("inf value", "load.amplitude = inf, 0.3", "", 2),
        ("hex float", "load.amplitude = 0x1p-2, 0.3", "", 2),
        ("duplicates 0.5 0.50", "load.amplitude = 0.5, 0.50", "", 2),
        ("key twice", "load.amplitude = 0.3\nload.amplitude = 0.4", "", 2),
        ("max_grid_n 1e9", "load.amplitude = 0.3", "max_grid_n = 1e9", 2),
        ("max_grid_n 1", "load.amplitude = 0.3", "max_grid_n = 1", 2),
        ("max_grid_n 64", "load.amplitude = 0.3, 0.05", "max_grid_n = 64", 0),
        ("zip unequal", "load.amplitude = 0.3,0.4\nsurface.radius = 1e-2", "combine = zip", 2),
        ("combine bogus", "load.amplitude = 0.3", "combine = cartesian", 2),
        ("scenario is a folder", "load.amplitude = 0.3", f"scenario = {SC}", 2),
        ("unknown study key", "load.amplitude = 0.3", "jobs = 2", 2),
        ("vary output.dir", "output.dir = a, b", "", 0),
        ("vary grid.n", "grid.n = 16, 24", "", 0),
        ("vary wear off", "wear.law = none, archard", "", 2),
        ("member fails", "solver.max_iterations = 5000, 1", "", 0),
        ("text values", "solver.algorithm = projected, partition", "", 0),
        ("product 10^12", "surface.seed = linear(1, 1000000, 1000000)\n"
                          "load.amplitude = linear(0.1, 0.5, 1000000)", "", 2),
    ]:
        add("sweep", name, sw("s.ini"), expect=exp if name != "member fails" else 4,
            setup=lambda w, v=vary, e=extra: study(w, "s.ini", v, e))
    add("sweep", "empty study file", sw("s.ini"), expect=2,
        setup=lambda w: write(os.path.join(w, "s.ini"), ""))
    add("sweep", "study file with BOM and CRLF", sw("s.ini"), expect=0,
        setup=lambda w: write(os.path.join(w, "s.ini"),
                              f"\ufeff[study]\r\nscenario = {MINDLIN}\r\nset = grid.n=16\r\n"
                              "set = load.cycles=1\r\n[vary]\r\nload.amplitude = 0.3\r\n"))
    add("sweep", "study file is a folder", [fb, "sweep", SC, "--out", "@W/sw"], expect=2)
    add("sweep", "study file missing", [fb, "sweep", "/nonexistent", "--out", "@W/sw"],
        expect=2)
    add("sweep", "out is a file", sw("s.ini"), expect=2,
        setup=lambda w: (study(w, "s.ini", "load.amplitude = 0.3"),
                         write(os.path.join(w, "sw"), "x")))
    for name, args, exp in [("member 5 of 2", ["--member", "5"], 2),
                            ("member -1", ["--member", "-1"], 2),
                            ("member huge", ["--member", "99999999999999999999"], 2),
                            ("jobs -1", ["--jobs", "-1"], 2), ("jobs 0", ["--jobs", "0"], 0),
                            ("list and member", ["--list", "--member", "0"], 2),
                            ("aggregate nothing run", ["--aggregate"], 0),
                            ("member 1", ["--member", "1"], 0), ("list", ["--list"], 0)]:
        add("sweep", name, sw("s.ini", *args), expect=exp,
            setup=lambda w: study(w, "s.ini", "load.amplitude = 0.3, 0.5"))
    longer = ("grid.n=32", "load.cycles=2", "load.steps_per_cycle=64",
              "output.checkpoint_every=5")
    add("sweep", "SIGTERM mid-run", sw("s.ini", "--jobs", "2"), expect=143, signal_after=1.5,
        setup=lambda w: study(w, "s.ini", "load.amplitude = 0.3, 0.5, 0.7, 0.8", sets=longer))
    mpirun = ["mpirun", "--allow-run-as-root", "--oversubscribe"]
    if shutil.which("mpirun"):
        add("mpi", "np 2 sweep", mpirun + ["-np", "2"] + sw("s.ini"), expect=0, timeout=120,
            setup=lambda w: study(w, "s.ini", "load.amplitude = 0.3, 0.5, 0.7"))
        add("mpi", "np 3 two members", mpirun + ["-np", "3"] + sw("s.ini"), expect=0,
            timeout=120, setup=lambda w: study(w, "s.ini", "load.amplitude = 0.3, 0.5"))
        add("mpi", "np 2 --member 1", mpirun + ["-np", "2"] + sw("s.ini", "--member", "1"),
            expect=0, timeout=120,
            setup=lambda w: study(w, "s.ini", "load.amplitude = 0.3, 0.5"))
        add("mpi", "np 2 --aggregate", mpirun + ["-np", "2"] + sw("s.ini", "--aggregate"),
            expect=0, timeout=120,
            setup=lambda w: study(w, "s.ini", "load.amplitude = 0.3, 0.5"))
        add("mpi", "np 2 bad study", mpirun + ["-np", "2"] + sw("s.ini"), expect=2,
            timeout=120, setup=lambda w: study(w, "s.ini", "load.amplitude = 0.3, 1.5"))

    # ---- wear
    wbase = run + [WEAR, "--set", "grid.n=16", "--set", "grid.length=1.4e-4"] + rq
    for integ in ("cycle", "erk", "dirk", "arkode"):
        wi = wbase + ["--set", f"wear.integrator={integ}"]
        for key, vals in [("wear.cycles", ["0", "-5", "1e-300", "1", "1.5", "2", "1e300",
                                           "nan", "inf", "9007199254740993", "1e15"]),
                          ("wear.coefficient", ["0", "-1e-14", "1e-300", "1e300", "nan", "inf",
                                                "1e-6"]),
                          ("wear.rtol", ["0", "-1", "1e-300", "1e300", "nan", "1"]),
                          ("wear.atol", ["0", "-1", "1e-300", "1e300", "nan"]),
                          ("wear.indenter_share", ["-0.1", "1.1", "0", "0.5", "nan"]),
                          ("wear.newton", ["frozen", "krylov", "bogus"])]:
            for v in vals:
                if integ in ("cycle", "erk") and v in ("9007199254740993", "1e15"):
                    continue  # every cycle simulated / explicit cap: a run of days, by request
                cyc = [] if key == "wear.cycles" else ["--set", "wear.cycles=100"]
                add("wear", f"{integ} {key}={v}", wi + cyc + ["--set", f"{key}={v}"],
                    timeout=120)
        add("wear", f"{integ} energy law", wi + ["--set", "wear.law=energy", "--set",
                                                  "wear.cycles=50"], expect=0, timeout=120)
        add("wear", f"{integ} gross slip", run + [GROSS, "--set", "grid.n=16", "--set",
                                                  "grid.length=1.4e-4", "--set",
                                                  f"wear.integrator={integ}", "--set",
                                                  "wear.cycles=200"] + rq,
            expect=0, timeout=120)
        add("wear", f"{integ} SIGTERM", wbase + ["--set", f"wear.integrator={integ}",
                                                "--set", "wear.cycles=100000", "--set",
                                                "wear.coefficient=1e-12"],
            expect=143, signal_after=1.0, timeout=120)
    add("wear", "law bogus", wbase + ["--set", "wear.law=bogus"], expect=2)
    add("wear", "integrator bogus", wbase + ["--set", "wear.integrator=rk4"], expect=2)
    add("wear", "fields wear every step", wbase + ["--set", "wear.cycles=20", "--set",
                                                  "output.fields=wear,pressure", "--set",
                                                  "output.fields_every=1"], expect=0)
    add("wear", "table one period", run + [WEAR, "--set", "grid.n=16", "--set",
                                           "grid.length=1.4e-4", "--set", "load.path=table",
                                           "--set", "load.table=@W/t.csv", "--set",
                                           "wear.cycles=20"] + rq, expect=0,
        setup=lambda w: write(os.path.join(w, "t.csv"),
                              "time,Fx\n0,0\n0.25,3\n0.5,0\n0.75,-3\n1,0\n"))
    add("wear", "table not a period", run + [WEAR, "--set", "grid.n=16", "--set",
                                             "grid.length=1.4e-4", "--set", "load.path=table",
                                             "--set", "load.table=@W/t.csv", "--set",
                                             "wear.cycles=20"] + rq, expect=2,
        setup=lambda w: write(os.path.join(w, "t.csv"), "time,Fx\n0,0\n0.5,3\n1,1\n"))

    # ---- load tables (driver: the Mindlin sphere, n = 16)
    tb = run + [MINDLIN, "--set", "grid.n=16", "--set", "load.path=table", "--set",
                "load.table=@W/t.csv"] + rq
    tables = {
        "single row": ("time,Fx\n0,1\n", 0),
        "header only": ("time,Fx\n", 2),
        "no time column": ("t,Fx\n0,1\n1,2\n", 2),
        "time not increasing": ("time,Fx\n0,0\n1,1\n0.5,2\n", 2),
        "duplicated time": ("time,Fx\n0,0\n1,1\n1,2\n", 2),
        "CRLF": ("time,Fx\r\n0,0\r\n1,1\r\n2,0\r\n", 0),
        "BOM": ("\ufefftime,Fx\n0,0\n1,1\n2,0\n", 0),
        "BOM and CRLF": ("\ufefftime,Fx\r\n0,0\r\n1,1\r\n", 0),
        "2-D Fx Fy": ("time,Fx,Fy\n0,0,0\n1,1,1\n2,-1,1\n3,0,0\n", 0),
        "2-D beyond mu in norm": ("time,Fx,Fy\n0,0,0\n1,4,4\n", 2),
        "varying Fz": ("time,Fz,Fx\n0,10,0\n1,20,3\n2,5,0\n3,10,-2\n", 0),
        "Fz to zero": ("time,Fz,Fx\n0,10,0\n1,0,0\n", 2),
        "Fz 1e-300": ("time,Fz,Fx\n0,10,0\n1,1e-300,0\n", 2),
        "Fz tiny positive": ("time,Fz,Fx\n0,10,0\n1,1e-9,0\n2,10,0\n", 0),
        "Fz negative": ("time,Fz,Fx\n0,10,0\n1,-5,0\n", 2),
        "Fz huge jump": ("time,Fz,Fx\n0,10,0\n1,1e6,0\n", 2),
        "Fz and delta": ("time,Fz,delta\n0,10,1e-7\n", 2),
        "Fx and Ux": ("time,Fx,Ux\n0,0,0\n1,1,1e-7\n", 2),
        "unknown column": ("time,Fx,Gx\n0,0,0\n1,1,1\n", 2),
        "duplicate column": ("time,Fx,Fx\n0,0,0\n1,1,1\n", 2),
        "empty cell": ("time,Fx\n0,0\n1,\n", 2),
        "text cell": ("time,Fx\n0,0\n1,abc\n", 2),
        "semicolons": ("time;Fx\n0;0\n1;1\n", 2),
        "decimal comma": ("time,Fx\n0,0\n1,\"1,5\"\n", 2),
        "extra cell": ("time,Fx\n0,0\n1,1,1\n", 2),
        "missing cell": ("time,Fx,Fy\n0,0,0\n1,1\n", 2),
        "inf": ("time,Fx\n0,0\n1,inf\n", 2),
        "negative time": ("time,Fx\n-1,0\n0,1\n1,0\n", 0),
        "time 1e-300 steps": ("time,Fx\n0,0\n1e-300,1\n2e-300,0\n", 2),
        "huge time": ("time,Fx\n0,0\n1e99,1\n", 0),
        "only comments": ("# nothing\n# here\n", 2),
        "NUL bytes": ("time,Fx\n0,0\n1,\x001\n", 2),
        "Ux table": ("time,Ux\n0,0\n1,1e-7\n2,-1e-7\n3,0\n", 0),
        "Ux 2-D": ("time,Ux,Uy\n0,0,0\n1,1e-7,1e-7\n2,0,0\n", 0),
        "delta table": ("time,delta,Fx\n0,1e-7,0\n1,2e-7,0\n", 0),
        "delta deeper than the domain": ("time,delta,Fx\n0,1e-7,0\n1,1,0\n", 2),
    }
    for name, (text, exp) in tables.items():
        extra = []
        if name.startswith("Ux"):
            extra = ["--set", "load.control=displacement"]
        argv = tb + extra
        if "Fz" in text.split("\n")[0] or "delta" in text.split("\n")[0]:
            argv = [x if x != MINDLIN else VARYING for x in argv]  # no constant normal load
        add("table", name, argv, expect=exp,
            setup=lambda w, t=text: write(os.path.join(w, "t.csv"), t))
    big = "time,Fx\n" + "".join(f"{i},{(i % 2) * 0.5}\n" for i in range(200000))
    add("table", "200000 rows", [fb, "check", MINDLIN, "--no-estimate", "--set", "grid.n=16",
                                 "--set", "load.path=table", "--set", "load.table=@W/t.csv"],
        expect=0, setup=lambda w: write(os.path.join(w, "t.csv"), big))
    add("table", "long line", tb, expect=2,
        setup=lambda w: write(os.path.join(w, "t.csv"), "time,Fx\n0," + "1" * 2000000 + "\n"))
    add("table", "binary garbage", tb, expect=2,
        setup=lambda w: write(os.path.join(w, "t.csv"), bytes(range(256)) * 10, "wb"))
    add("table", "table is a folder", run + [MINDLIN, "--set", "grid.n=16", "--set",
                                             "load.path=table", "--set", f"load.table={SC}"]
        + rq, expect=2)
    add("table", "table is /dev/zero", run + [MINDLIN, "--set", "grid.n=16", "--set",
                                              "load.path=table", "--set",
                                              "load.table=/dev/zero"] + rq, expect=2,
        timeout=30)

    # ---- height maps (driver: a flat punch replaced by file, n = 16)
    hm = run + [MINDLIN, "--set", "grid.n=16", "--set", "grid.length=1.6e-4", "--set",
                "surface.type=file", "--set", "load.amplitude=0.3"] + rq

    def surf(name, fname, data, exp, extra=(), mode="w"):
        add("surface", name, hm + ["--set", f"surface.file=@W/{fname}", *extra], expect=exp,
            setup=lambda w: write(os.path.join(w, fname), data, mode))

    dome = [[-((i - 7.5) ** 2 + (j - 7.5) ** 2) * 1e-8 for i in range(16)] for j in range(16)]
    dome_txt = "\n".join(" ".join(repr(v) for v in row) for row in dome) + "\n"
    flatv = [v for row in dome for v in row]
    surf("text dome", "z.txt", dome_txt, 0)
    surf("text empty", "z.txt", "", 2)
    surf("text one value", "z.txt", "0\n", 2)
    surf("text 16x15", "z.txt", "\n".join(dome_txt.splitlines()[:15]) + "\n", 2)
    surf("text 15 cols", "z.txt", "\n".join(" ".join(l.split()[:15])
                                           for l in dome_txt.splitlines()) + "\n", 2)
    surf("text nan", "z.txt", dome_txt.replace(dome_txt.split()[3], "nan", 1), 2)
    surf("text inf", "z.txt", dome_txt.replace(dome_txt.split()[3], "inf", 1), 2)
    surf("text CRLF", "z.txt", dome_txt.replace("\n", "\r\n"), 0)
    surf("text BOM", "z.txt", "\ufeff" + dome_txt, 0)
    surf("text commas", "z.txt", dome_txt.replace(" ", ","), 2)
    surf("text all equal", "z.txt", flat_text(16, "0"), 0)
    surf("npy dome", "z.npy", npy_bytes((16, 16), flatv), 0, mode="wb")
    surf("npy f4", "z.npy", npy_bytes((16, 16), flatv, "<f4"), 0, mode="wb")
    surf("npy big-endian", "z.npy", npy_bytes((16, 16), flatv, ">f8"), 2, mode="wb")
    surf("npy int32", "z.npy", npy_bytes((16, 16), [0] * 256, "<i4"), 2, mode="wb")
    surf("npy fortran", "z.npy", npy_bytes((16, 16), flatv, fortran=True), 0, mode="wb")
    surf("npy 1-D", "z.npy", npy_bytes((256,), flatv), 2, mode="wb")
    surf("npy 3-D", "z.npy", npy_bytes((16, 16, 1), flatv), 2, mode="wb")
    surf("npy 16x8", "z.npy", npy_bytes((16, 8), flatv[:128]), 2, mode="wb")
    surf("npy truncated", "z.npy", npy_bytes((16, 16), flatv)[:-100], 2, mode="wb")
    surf("npy huge header shape", "z.npy",
         npy_bytes((16, 16), flatv, header_shape=(1 << 40, 1 << 40)), 2, mode="wb")
    surf("npy negative shape", "z.npy", npy_bytes((16, 16), flatv, header_shape=(-16, -16)),
         2, mode="wb")
    surf("npy nan", "z.npy", npy_bytes((16, 16), [float("nan")] + flatv[1:]), 2, mode="wb")
    surf("npy empty file", "z.npy", b"", 2, mode="wb")
    surf("npy magic only", "z.npy", b"\x93NUMPY\x01\x00", 2, mode="wb")
    surf("npy header len huge", "z.npy", b"\x93NUMPY\x01\x00\xff\xff{", 2, mode="wb")
    surf("npy version 3", "z.npy", b"\x93NUMPY\x03\x00" + npy_bytes((16, 16), flatv)[8:], 2,
         mode="wb")
    surf("unknown extension", "z.dat", dome_txt, 0)
    surf("x3p garbage", "z.x3p", b"PK\x03\x04garbage", 2, mode="wb")
    surf("npz garbage", "z.npz", b"PK\x03\x04garbage", 2, mode="wb")
    surf("h5 garbage", "z.h5", b"\x89HDF\r\n\x1a\ngarbage", 2, mode="wb")
    add("surface", "file missing", hm + ["--set", "surface.file=@W/nothere.txt"], expect=2)
    add("surface", "file is a folder", hm + ["--set", f"surface.file={SC}"], expect=2)
    add("surface", "file is /dev/zero", hm + ["--set", "surface.file=/dev/zero"], expect=2,
        timeout=30)

    # ---- output options
    for name, sets, exp in [
        ("fields all every 1", ["output.fields=pressure,traction_x,traction_y,state,slip_x,"
                                "slip_y,dissipation", "output.fields_every=1"], 0),
        ("fields bogus", ["output.fields=pressure,bogus"], 2),
        ("fields empty", ["output.fields="], 0),
        ("fields repeated", ["output.fields=pressure,pressure"], 0),
        ("fields none", ["output.fields=none"], 0),
        ("fields_every -1", ["output.fields_every=-1"], 2),
        ("fields_every 1e30", ["output.fields_every=1e30"], 2),
        ("fields_every 1.5", ["output.fields_every=1.5"], 2),
        ("fields_every huge", ["output.fields=pressure", "output.fields_every=1000000000"], 0),
        ("checkpoint_every -1", ["output.checkpoint_every=-1"], 2),
        ("checkpoint_every 1", ["output.checkpoint_every=1"], 0),
        ("fields wear without wear", ["output.fields=wear"], 0),
        ("output.dir empty", ["output.dir="], 2),
    ]:
        add("output", name, run + [MINDLIN, "--set", "grid.n=16", "--set", "load.cycles=1",
                                   "--set", "load.steps_per_cycle=8"]
            + [x for s in sets for x in ("--set", s)] + rq, expect=exp)

    # ---- check --estimate
    for name, args, exp in [
        ("mindlin", [MINDLIN, *SMALL], 0), ("wear", [WEAR, *SMALL], 0),
        ("rough", [ROUGH, *SMALL], 0), ("varying", [VARYING, *SMALL], 0),
        ("wear cycles 1e15", [WEAR, *SMALL, "--set", "wear.cycles=1e15"], 0),
        ("wear k 1e-6", [WEAR, *SMALL, "--set", "wear.coefficient=1e-6"], 0),
        ("iterations 1", [MINDLIN, *SMALL, "--set", "solver.max_iterations=1"], 0),
        ("iterations 0", [MINDLIN, *SMALL, "--set", "solver.max_iterations=0"], 2),
        ("normal only", [MINDLIN, *SMALL, "--set", "load.path=none"], 0),
        ("ramp 1 step", [MINDLIN, *SMALL, "--set", "load.path=ramp", "--set", "load.steps=1"],
         0),
        ("ramp 0 steps", [MINDLIN, *SMALL, "--set", "load.path=ramp", "--set", "load.steps=0"],
         2),
        ("stop-after (a run option)", [MINDLIN, *SMALL, "--stop-after", "3"], 0),
        ("hurst (an ensemble option)", [MINDLIN, *SMALL, "--hurst", "0.5"], 2),
    ]:
        add("check", name, [fb, "check", *args], expect=exp)

    # ---- plot tools on damaged or empty result folders
    tools = os.path.join(ROOT, "tools")
    for tool, extra in [("plot_hysteresis.py", []), ("plot_fields.py", []),
                        ("plot_wear.py", []), ("plot_surface.py", []),
                        ("plot_paper_figures.py", []),
                        ("plot_energy_per_cycle.py", []),
                        ("plot_fig3_contact_fraction.py", [])]:
        for damage in ("empty folder", "missing folder", "header-only csv", "garbage h5",
                       "torn csv"):
            add("tools", f"tool:{tool} {damage}",
                [PY, os.path.join(tools, tool), "@W/r", *extra, "--out", "@W/p.png"],
                setup=lambda w, d=damage: damage_folder(w, d), timeout=60)
    return out


def damage_folder(work, damage):
    r = os.path.join(work, "r")
    if damage == "missing folder":
        return
    os.makedirs(r, exist_ok=True)
    if damage == "header-only csv":
        for n in ("timeseries.csv", "cycles.csv", "sweep.csv", "members.csv", "aggregate.csv"):
            write(os.path.join(r, n), "step,time,cycle,Fz,delta,Fx,Fy,Ux,Uy\n")
    elif damage == "garbage h5":
        write(os.path.join(r, "result.h5"), b"\x89HDF\r\n\x1a\n" + b"\0" * 100, "wb")
        write(os.path.join(r, "timeseries.csv"), "step,time\n0,0\n")
    elif damage == "torn csv":
        write(os.path.join(r, "timeseries.csv"), "step,time,cycle,Fz,delta,Fx\n0,0,0,10,1e-")
        write(os.path.join(r, "cycles.csv"), "cycle,steps,dissipated_en")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("build")
    ap.add_argument("--filter", default="")
    ap.add_argument("--list", action="store_true")
    ap.add_argument("--keep", help="keep each case's folder below DIR")
    args = ap.parse_args()
    all_cases = [c for c in cases(os.path.abspath(args.build))
                 if args.filter in f"{c.area}: {c.name}"]
    if args.list:
        for c in all_cases:
            print(f"{c.area}: {c.name}")
        return 0
    per_area, flagged = {}, 0
    for i, c in enumerate(all_cases):
        work = tempfile.mkdtemp(prefix="hunt_", dir=args.keep)
        code, err, dt = run_case(c, work)
        flags = judge(c, code, err, dt, work)
        a = per_area.setdefault(c.area, [0, 0])
        a[0] += 1
        if flags:
            a[1] += 1
            flagged += 1
        line = err.strip().splitlines()[-1][:160] if err.strip() else ""
        print(f"{'FLAG' if flags else 'ok  '} {c.area}: {c.name}: exit {code} {dt:.1f}s "
              f"{' '.join(flags)} | {line}", flush=True)
        if not args.keep:
            shutil.rmtree(work, ignore_errors=True)
    print("\n| area | cases | flagged |\n|---|---|---|")
    for a, (n, f) in per_area.items():
        print(f"| {a} | {n} | {f} |")
    print(f"| all | {sum(v[0] for v in per_area.values())} | {flagged} |")
    return 1 if flagged else 0


if __name__ == "__main__":
    sys.exit(main())
