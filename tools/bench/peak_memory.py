#!/usr/bin/python3
"""Peak RSS of one `fretbem run` against `fretbem check`'s memory estimate (docs/performance.md,
"Memory").

usage: tools/bench/peak_memory.py BINARY LABEL SCENARIO [section.key=value ...]
           [--stop-after N]

Prints one tab-separated line: label, exit code, the estimate and the peak RSS (MiB, the
child's own ru_maxrss from wait4), their ratio, CPU and wall seconds, and the load average.
The run writes to fretbem-peak-memory/LABEL in the temporary folder ($TMPDIR, else the
system's; replaced).
"""
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time


def main(argv):
    stop_after = []
    if "--stop-after" in argv:
        i = argv.index("--stop-after")
        stop_after = ["--stop-after", argv[i + 1]]
        del argv[i:i + 2]
    binary, label, scenario, *sets = argv
    out = os.path.join(tempfile.gettempdir(), "fretbem-peak-memory", label)
    shutil.rmtree(out, ignore_errors=True)
    set_args = [a for s in sets for a in ("--set", s)]
    check = subprocess.run([binary, "check", scenario, *set_args, "--no-estimate"],
                           capture_output=True, text=True)
    m = re.search(r"memory: about ([0-9.e+]+) MiB", check.stdout)
    estimate = float(m.group(1)) if m else float("nan")
    t0 = time.time()
    with open(os.devnull, "w") as null:
        child = subprocess.Popen([binary, "run", scenario, *set_args, *stop_after, "--out", out,
                                  "--overwrite", "--quiet"], stdout=null)
        _, status, usage = os.wait4(child.pid, 0)
    wall = time.time() - t0
    peak = usage.ru_maxrss / 1024.0
    print(f"{label}\trc={os.waitstatus_to_exitcode(status)}\testimate={estimate:.0f} MiB\t"
          f"peak={peak:.1f} MiB\tratio={estimate / peak:.2f}\t"
          f"cpu={usage.ru_utime + usage.ru_stime:.1f} s\twall={wall:.1f} s\t"
          f"load={os.getloadavg()[0]:.1f}", flush=True)


if __name__ == "__main__":
    main(sys.argv[1:])
