#!/usr/bin/env python3
"""Bad-input corpus: every case through `fretbem check` and `fretbem run`.

Usage: run_corpus.py FRETBEM_BINARY [CORPUS_DIR]

A case is a file with a sidecar NAME.expect next to it:
    exit 2                  expected exit code of `run` (and of `check`, unless check_exit)
    check_exit 0            optional: `check`'s code when it differs (only a solve finds it)
    stderr load.table       a substring stderr must contain (case-sensitive; repeatable)
    set section.key=value   optional --set for both commands (repeatable)
scenarios/*.ini run as they are; tables/* drive tables/driver.ini through load.table;
surfaces/* drive surfaces/driver.ini through surface.file. Every failure must be one line
on stderr that names the key, file or value: no C++ library text, no crash, no hang.
"""
import os
import subprocess
import sys
import tempfile

TIMEOUT = 20  # s per command; a hang is a failure
LIBRARY_TEXT = ("std::", "basic_", "bad_alloc", "filesystem error", "terminate", "Assertion")


def read_expect(path):
    exp = {"exit": None, "check_exit": None, "stderr": [], "set": []}
    with open(path, encoding="utf-8") as f:
        for line in f:
            line = line.strip()
            if not line or line.startswith("#"):
                continue
            key, _, value = line.partition(" ")
            if key in ("exit", "check_exit"):
                exp[key] = int(value)
            elif key in ("stderr", "set"):
                exp[key].append(value)
            else:
                raise SystemExit(f"{path}: unknown line '{line}'")
    if exp["exit"] is None:
        raise SystemExit(f"{path}: no 'exit' line")
    return exp


def command_for(corpus, case):
    kind = os.path.basename(os.path.dirname(case))
    if kind == "scenarios":
        return case, []
    if kind == "tables":
        return os.path.join(corpus, "tables", "driver.ini"), [f"load.table={case}"]
    if kind == "surfaces":
        return os.path.join(corpus, "surfaces", "driver.ini"), [f"surface.file={case}"]
    raise SystemExit(f"{case}: not in scenarios/, tables/ or surfaces/")


def run(argv):
    try:
        p = subprocess.run(argv, capture_output=True, text=True, errors="replace",
                           timeout=TIMEOUT)
        return p.returncode, p.stderr
    except subprocess.TimeoutExpired:
        return "timeout", ""


def check_one(binary, corpus, case, exp, out_dir):
    scenario, sets = command_for(corpus, case)
    sets = sets + exp["set"]
    set_args = [a for s in sets for a in ("--set", s)]
    problems = []
    for cmd, want in (("check", exp["check_exit"] if exp["check_exit"] is not None
                       else exp["exit"]), ("run", exp["exit"])):
        argv = [binary, cmd, scenario, *set_args]
        if cmd == "run":
            argv += ["--quiet", "--out", out_dir]
        code, err = run(argv)
        if code != want:
            problems.append(f"{cmd}: exit {code}, expected {want}; stderr: {err.strip()[:300]}")
            continue
        if want == 0:
            continue
        lines = [l for l in err.splitlines() if l.strip()]
        if len(lines) != 1:
            problems.append(f"{cmd}: {len(lines)} stderr lines, expected one: {err[:300]}")
        for s in exp["stderr"]:
            if s not in err:
                problems.append(f"{cmd}: stderr does not name '{s}': {err.strip()[:300]}")
        for s in LIBRARY_TEXT:
            if s in err:
                problems.append(f"{cmd}: stderr shows library text '{s}': {err.strip()[:300]}")
    return problems


def main():
    binary = os.path.abspath(sys.argv[1])
    corpus = os.path.abspath(sys.argv[2] if len(sys.argv) > 2 else os.path.dirname(__file__))
    cases = []
    for kind in ("scenarios", "tables", "surfaces"):
        folder = os.path.join(corpus, kind)
        for name in sorted(os.listdir(folder)):
            if name.endswith(".expect") or name == "driver.ini" or os.path.isdir(os.path.join(folder, name)):
                continue
            stem = os.path.join(folder, os.path.splitext(name)[0])
            if not os.path.exists(stem + ".expect"):
                raise SystemExit(f"{os.path.join(folder, name)}: no {stem}.expect")
            cases.append((os.path.join(folder, name), read_expect(stem + ".expect")))
    failed = 0
    with tempfile.TemporaryDirectory() as tmp:
        for i, (case, exp) in enumerate(cases):
            problems = check_one(binary, corpus, case, exp, os.path.join(tmp, f"out{i}"))
            rel = os.path.relpath(case, corpus)
            print(("FAIL " if problems else "ok   ") + rel)
            for p in problems:
                print("     " + p)
            failed += bool(problems)
    print(f"{len(cases) - failed} of {len(cases)} bad-input cases pass")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
