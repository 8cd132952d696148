"""Seeded scenario cases for the combination sweep (combination_sweep.py).

draw_case(seed, index) returns a Case: every scenario key a user can combine (README, "Scenario
files"), drawn at random but sized so that a run takes 0.1-2 s (n = 16-48, few steps), plus the
input files it needs (height maps in .npy/.txt/.h5/.npz, load tables) and the interruption to
try (none, `--stop-after K`, SIGTERM at once, in step 0 or after k rows). The same
(seed, index) always gives the same case, so any case can be rerun alone. The load-step keys
(`load.substeps`, `load.tolerance`, `load.interpolation`) come from a stream of their own, so
the other keys of a (seed, index) stay those it drew before they were added. Lengths in m,
forces in N, moduli in Pa.
"""
import io
import math
import random

import numpy as np

RADIUS = 0.01    # sphere radius (m), as the shipped scenarios
LENGTH = 2.8e-4  # domain side (m), as the shipped scenarios


class Limits:
    """How large a drawn case may be: grid sizes (wear runs and costly cases take the smaller
    list), wear cycle counts (`cycle` mode simulates every one), the largest grid for the
    `coupled` alternation (about ten times the CPU of `cerruti`, README), the most FFT threads
    (two threads at n <= 32 took 40-60 times the CPU of one on the loaded machine,
    docs/reliability.md, "Combination sweep"), whether cases are also run on two MPI ranks."""

    def __init__(self, grids, small_grids, wear_cycles, cycle_mode_cycles, coupled_max_n,
                 max_threads, mpi=True):
        self.grids, self.small_grids = grids, small_grids
        self.wear_cycles, self.cycle_mode_cycles = wear_cycles, cycle_mode_cycles
        self.coupled_max_n, self.max_threads = coupled_max_n, max_threads
        self.mpi = mpi


FULL = Limits([16, 24, 32, 48], [16, 24, 32], [3, 10, 40, 200, 1000, 20000], [3, 10, 40, 200],
              48, 2)
# The ctest subset: under two minutes on the shared two-core machine at load ~16; without the
# MPI reruns, which took it from 6.4 s to 29.8 s of wall time (load average 2.4 and 5).
QUICK = Limits([16, 24], [16], [3, 10, 40], [3, 10, 40], 16, 1, mpi=False)


class Case:
    """One combination: INI keys, input files (name -> bytes), the interruption to try, and
    the reruns (draw_reruns): on two MPI ranks, with --overwrite."""

    def __init__(self, index, keys, files, mode, mode_arg, notes):
        self.index, self.keys, self.files = index, keys, files
        self.mode, self.mode_arg, self.notes = mode, mode_arg, notes
        self.mpi, self.overwrite = False, None

    def ini(self):
        sections = {}
        for key, value in self.keys.items():
            section, name = key.split(".", 1)
            sections.setdefault(section, []).append(f"{name} = {value}")
        return "".join(f"[{s}]\n" + "\n".join(lines) + "\n\n" for s, lines in sections.items())

    def get(self, key, default=None):
        return self.keys.get(key, default)

    def is_wear(self):
        return self.get("wear.law", "none") != "none"

    def mu_max(self):
        """The largest friction coefficient any node can have (bounds |F_t| / F_z)."""
        mus = [float(self.get("material.mu", 0.3))]
        for key in ("friction.mu_kinetic", "friction.mu_final"):
            if key in self.keys:
                mus.append(float(self.keys[key]))
        return max(mus)

    def varying_normal(self):
        return "varying_normal" in self.notes

    def subdivides(self):
        """Whether the load-step keys ask for more than one solve a row (README, load.*)."""
        return int(self.get("load.substeps", 1)) > 1 or float(self.get("load.tolerance", 0)) > 0

    def steps_refused(self):
        """Wear runs refuse `load.tolerance` > 0 and an explicit `load.substeps` > 1 (README)."""
        return self.is_wear() and self.subdivides()

    def bound_moves(self):
        """Whether the Coulomb bound mu p moves within steps, so that nodes can lose contact:
        a varying normal load, a surface worn between cycles, or the coupled alternation."""
        return self.varying_normal() or self.is_wear() or self.get("solver.coupling") == "coupled"


def e_star(keys):
    def term(E, nu):
        return (1 - nu * nu) / E

    inv = term(keys["material.E"], keys["material.nu"])
    if "material.E2" in keys:
        inv += term(keys["material.E2"], keys["material.nu2"])
    return 1.0 / inv


def g_star(keys):
    def term(E, nu):
        return (2 - nu) / (4 * E / (2 * (1 + nu)))

    inv = term(keys["material.E"], keys["material.nu"])
    if "material.E2" in keys:
        inv += term(keys["material.E2"], keys["material.nu2"])
    return 1.0 / inv


class Scales:
    """Hertz-like scales of the drawn contact: normal force P, approach delta, pressure p0,
    full-sliding shift U* = mu delta E*/G*."""

    def __init__(self, P, delta, p0, mu, es, gs):
        self.P, self.delta, self.p0 = P, delta, p0
        self.u_star = mu * delta * es / gs


def draw_material(r, k):
    k["material.E"] = r.choice([210e9, 70e9, 5e9])
    k["material.nu"] = r.choice([0.3, 0.0, 0.25, 0.49])
    k["material.mu"] = r.choice([0.3, 0.5, 0.8])
    if r.random() < 0.3:
        k["material.E2"] = r.choice([210e9, 70e9])
        k["material.nu2"] = r.choice([0.3, 0.33])


def draw_grid(r, k, wear, costly, limits):
    n = r.choice(limits.small_grids if wear or costly else limits.grids)
    if r.random() < 0.1:
        k["grid.nx"], k["grid.ny"] = n, r.choice([n // 2, n])
    else:
        k["grid.n"] = n
    k["grid.length"] = LENGTH
    if r.random() < 0.2:
        k["grid.periodic"] = "true"
    if r.random() < 0.1:
        k["grid.allow_edge_contact"] = "true"
    return n


def sphere_heights(nx, ny, h):
    x = (np.arange(nx) - (nx - 1) / 2) * h
    y = (np.arange(ny) - (ny - 1) / 2) * h
    X, Y = np.meshgrid(x, y)  # [ny][nx], the "yx" layout
    return -(X * X + Y * Y) / (2 * RADIUS)


def rough_heights(r, nx, ny, h, rms_slope):
    """A Gaussian random surface with a power-law spectrum, scaled to rms_slope."""
    rng = np.random.default_rng(r.randrange(2**32))
    qx = np.fft.fftfreq(nx)[None, :]
    qy = np.fft.fftfreq(ny)[:, None]
    q = np.hypot(qx, qy)
    q[0, 0] = 1.0
    spectrum = q ** -1.8 * np.exp(1j * rng.uniform(0, 2 * np.pi, (ny, nx)))
    spectrum[0, 0] = 0.0
    z = np.real(np.fft.ifft2(spectrum))
    slope = np.sqrt(np.mean(np.gradient(z, h)[0] ** 2 + np.gradient(z, h)[1] ** 2))
    return z * rms_slope / slope


def height_file(r, z, layout):
    """A height map in a randomly chosen format; returns (file name, bytes, extra keys)."""
    a = z.T.copy() if layout == "xy" else z
    fmt = r.choice(["npy", "txt", "h5", "npz"])
    buf = io.BytesIO()
    extra = {}
    if fmt == "npy":
        np.save(buf, a)
    elif fmt == "txt":
        np.savetxt(buf, a, fmt="%.17g")
    elif fmt == "npz":
        np.savez(buf, heights=a)
        if r.random() < 0.5:
            extra["surface.dataset"] = "heights"
    else:
        import h5py
        with h5py.File(buf, "w") as f:
            f["heights"] = a
        extra["surface.dataset"] = "heights"
    return f"surface.{fmt}", buf.getvalue(), extra


def draw_surface(r, k, files, nx, ny):
    """Surface keys and files; returns the scales of the contact they make."""
    es, gs = e_star(k), g_star(k)
    mu = k["material.mu"]
    h = LENGTH / nx
    kind = r.choices(["sphere", "flat", "rough", "file"], [0.45, 0.1, 0.25, 0.2])[0]
    k["surface.type"] = kind
    if kind in ("sphere", "file") and (kind == "sphere" or r.random() < 0.5):
        a = LENGTH * r.choice([0.15, 0.25, 0.3])
        P = 4 * es * a**3 / (3 * RADIUS)
        if kind == "sphere":
            k["surface.radius"] = RADIUS
        else:
            layout = r.choice(["yx", "xy"])
            name, data, extra = height_file(r, sphere_heights(nx, ny, h), layout)
            files[name] = data
            k.update(extra)
            k["surface.file"], k["surface.layout"] = name, layout
        return Scales(P, a * a / RADIUS, 3 * P / (2 * math.pi * a * a), mu, es, gs)
    slope = r.choice([0.02, 0.05])
    if kind == "rough":
        k["surface.method"] = r.choice(["midpoint", "fourier"])
        k["surface.hurst"] = r.choice([0.3, 0.7, 1.0])
        k["surface.seed"] = r.randrange(1, 1000)
        if r.random() < 0.5:
            k["surface.rms_slope"] = slope
        else:
            k["surface.rms_height"] = slope * LENGTH / 20
        if k["surface.method"] == "fourier" and r.random() < 0.5:
            k["surface.rolloff_wavelength"] = LENGTH / 4
            k["surface.cutoff_wavelength"] = 3 * h
    elif kind == "file":
        layout = r.choice(["yx", "xy"])
        name, data, extra = height_file(r, rough_heights(r, nx, ny, h, slope), layout)
        files[name] = data
        k.update(extra)
        k["surface.file"], k["surface.layout"] = name, layout
    # Nominally flat contacts: a mean pressure of a few per cent of E* times the slope
    # (contact fraction ~ 10-40 %); the flat punch fills the domain.
    p_mean = es * (0.001 if kind == "flat" else slope * r.choice([0.1, 0.3]))
    P = p_mean * LENGTH * LENGTH * ny / nx
    delta = (slope * LENGTH / 20) * 3 if kind != "flat" else P / (es * LENGTH)
    return Scales(P, delta, p_mean * (1 if kind == "flat" else 5), mu, es, gs)


def draw_friction(r, k, wear_integrator):
    mu = k["material.mu"]
    law = r.choices(["constant", "static_kinetic", "evolving"], [0.5, 0.25, 0.25])[0]
    if law == "evolving" and wear_integrator not in (None, "cycle") and r.random() < 0.8:
        law = "constant"  # documented refusal: drawn now and then, not every time
    if law == "constant":
        if r.random() < 0.3:
            k["friction.law"] = "constant"
        return mu
    k["friction.law"] = law
    if law == "static_kinetic":
        k["friction.mu_kinetic"] = round(mu * r.choice([0.6, 0.8, 1.2]), 6)
        return min(mu, k["friction.mu_kinetic"])
    k["friction.mu_final"] = round(mu * r.choice([0.7, 1.3]), 6)
    k["friction.evolution"] = r.choice(["dissipation", "slip_path"])
    return min(mu, k["friction.mu_final"])


def draw_solver(r, k, n, limits):
    k["solver.threads"] = min(r.choices([1, 2], [0.9, 0.1])[0], limits.max_threads)
    if r.random() < 0.1:
        k["solver.fft_precision"] = "float"
        k["solver.tolerance"] = r.choice([1e-6, 1e-5])
    else:
        k["solver.tolerance"] = r.choice([1e-8, 1e-6, 1e-10])
    k["solver.stiffness"] = r.choice(["every", "turning", "none", "true", "false"])
    k["solver.coupling"] = r.choices(["analogy", "cerruti", "coupled"], [0.5, 0.3, 0.2])[0]
    if k["solver.coupling"] == "coupled" and n > limits.coupled_max_n:
        k["solver.coupling"] = "cerruti"
    k["solver.algorithm"] = r.choices(["projected", "partition"], [0.85, 0.15])[0]
    k["solver.precondition"] = r.choice(["automatic", "on", "off"])
    k["solver.predictor"] = r.choice(["auto", "none", "cycle"])
    if r.random() < 0.1:
        k["solver.monotone"] = "shortcut"


def table_rows(r, periods, per_period, normal, tangential, P, delta, amp):
    """Rows of a periodic table: a tangential sine (1-D or an ellipse in 2-D) and, when asked,
    a normal load that varies by +-30 % at twice the frequency."""
    rows = []
    for i in range(periods * per_period + 1):
        t = i / per_period
        row = {"time": t}
        vary = 1 + 0.3 * math.sin(4 * math.pi * t)
        if normal == "Fz":
            row["Fz"] = P * vary
        elif normal == "delta":
            row["delta"] = delta * vary ** (2 / 3)  # Hertz: delta ~ P^(2/3)
        scale = amp * (vary if normal == "Fz" else 1.0)
        for c, phase in tangential:
            row[c] = scale * math.sin(2 * math.pi * t + phase)
        rows.append(row)
    cols = list(rows[0])
    text = ",".join(cols) + "\n"
    text += "".join(",".join(f"{row[c]:.17g}" for c in cols) + "\n" for row in rows)
    return text


def draw_table(r, k, files, s, control, mu_low, wear):
    normal = r.choices(["none", "Fz", "delta"], [0.4, 0.45, 0.15])[0]
    if normal == "delta" and k["surface.type"] != "sphere":
        normal = "Fz"
    two_d = r.random() < (0.2 if wear else 0.35)
    names = ("Ux", "Uy") if control == "displacement" else ("Fx", "Fy")
    tangential = [(names[0], 0.0)] + ([(names[1], r.choice([0.5, math.pi / 2]))] if two_d else [])
    if control == "displacement":
        amp = s.u_star * r.choice([0.3, 1.0, 3.0])
    else:
        # Peak |F_t| of the 2-D ellipse is at most sqrt(2) amp; stay below the lowest mu F_z.
        amp = r.choice([0.3, 0.6]) * mu_low * s.P / (math.sqrt(2) if two_d else 1.0)
    periods = 1 if wear else r.choice([1, 2])
    per_period = r.choice([8, 12])
    files["table.csv"] = table_rows(r, periods, per_period, normal, tangential, s.P, s.delta,
                                    amp).encode()
    k["load.table"] = "table.csv"
    notes = []
    if normal != "none":
        notes.append("varying_normal")
    if two_d:
        notes.append("two_d")
    return normal, notes


def draw_load(r, k, files, s, mu_low, path, wear):
    notes = []
    control = r.choices(["force", "displacement"], [0.6, 0.4])[0]
    if k.get("grid.periodic") == "true" and r.random() < 0.9:
        control = "force"  # documented restriction; drawn now and then to see it refused
    if path != "table" or r.random() < 0.9:
        k["load.control"] = control  # a table's Ux/Uy columns need displacement: else refused
    normal = "none"
    if path == "table":
        normal, notes = draw_table(r, k, files, s, control, mu_low, wear)
    if normal == "none":
        if k["surface.type"] == "sphere" and r.random() < 0.25:
            k["load.indentation"] = s.delta
        else:
            k["load.normal_force"] = s.P
    if path in ("ramp", "sine"):
        if control == "force":
            k["load.amplitude"] = round(r.choice([0.3, 0.6, 0.9]) * mu_low / k["material.mu"], 6)
        else:
            k["load.displacement_amplitude"] = s.u_star * r.choice([0.3, 1.0, 3.0, 20.0])
        if r.random() < 0.5:
            k["load.direction"] = r.choice([0, 30, 90, -45, 200])
    if path == "ramp":
        k["load.steps"] = r.choice([4, 8, 12])
    if path == "sine":
        k["load.cycles"] = r.choice([1, 2])
        k["load.steps_per_cycle"] = r.choice([8, 12, 16])
    return notes


def draw_wear(r, k, s, integ, limits):
    k["wear.law"] = r.choice(["archard", "energy"])
    k["wear.integrator"] = integ
    N = r.choice(limits.cycle_mode_cycles if integ == "cycle" else limits.wear_cycles)
    k["wear.cycles"] = N
    # k_eq p0 (4 U*) N = f delta: in gross slip the worn depth is about f x the indentation;
    # in partial slip (slip far below 4 U*) two to three decades less.
    f = r.choice([0.03, 0.3, 3.0, 30.0])
    k_eq = f * s.delta / (N * s.p0 * 4 * s.u_star)
    k["wear.coefficient"] = k_eq / (k["material.mu"] if k["wear.law"] == "energy" else 1.0)
    k["wear.rtol"] = r.choice([1e-3, 1e-2])
    if integ in ("dirk", "arkode") and r.random() < 0.3:
        k["wear.newton"] = "krylov"
    k["wear.indenter_share"] = r.choice([1, 0.5, 0])


def draw_output(r, k, wear):
    names = ["pressure", "traction_x", "traction_y", "state", "slip_x", "slip_y", "dissipation"]
    if wear:
        names.append("wear")
    if r.random() < 0.5:
        k["output.fields"] = ", ".join(r.sample(names, r.randint(1, 3)))
        k["output.fields_every"] = r.choice([0, 1, 3])
    if r.random() < 0.3:
        k["output.checkpoint_every"] = r.choice([1, 5])


def draw_mode(r, wear):
    mode = r.choices(["plain", "stop", "sigterm"], [0.4, 0.3, 0.3])[0]
    if mode == "stop":
        return mode, r.randint(1, 3 if wear else 6)
    if mode == "sigterm":
        # Rows of the time series to wait for; 0: until the output folder exists (step 0 in
        # progress); -1: not at all (the signal may arrive before the handler is installed).
        return mode, r.choice([-1, 0, 0, 1, 2, 4, 8])
    return mode, None


STEP_SUBSTEPS = [1, 2, 3, 4, 8]
STEP_TOLERANCES = [0, 1e-2, 3e-3, 1e-3]
STEP_MAX_N = 32  # sub-steps multiply a row's solves (8 of them, or up to 256 under tolerance)


def step_share(case):
    """How often a case draws the load-step keys: nearly always where they act (a table whose
    normal load varies, outside wear runs), sometimes where they must be no-ops (constant normal
    load) or refused (wear runs, README: `load.substeps` > 1 and `load.tolerance` > 0)."""
    if case.get("load.path") not in ("sine", "table"):
        return 0.0
    return 0.9 if case.varying_normal() and not case.is_wear() else 0.25


def draw_steps(seed, index, case, n):
    """Adds the load-step keys to a case of at most STEP_MAX_N cells a side; notes "steps", and
    "steps_pair" on some constant-load cases that the sweep reruns without them."""
    r = random.Random(f"combination-sweep-steps:{seed}:{index}")
    if n > STEP_MAX_N or r.random() >= step_share(case):
        return
    k = case.keys
    if r.random() < 0.8:
        k["load.substeps"] = r.choice(STEP_SUBSTEPS)
    if r.random() < 0.6:
        k["load.tolerance"] = r.choice(STEP_TOLERANCES)
    if r.random() < 0.7:
        k["load.interpolation"] = r.choice(["linear", "cubic"])
    if case.varying_normal() and case.subdivides() and r.random() < 0.4:
        k["solver.predictor"] = "cycle"  # it remembers each sub-step of a repeated row
    case.notes.append("steps")
    if case.subdivides() and not case.varying_normal() and not case.is_wear() and r.random() < 0.5:
        case.notes.append("steps_pair")
# Overwrite reruns: a clean replacement, one stopped by SIGTERM once it has written rows, one
# that fails (every solve capped at one iteration).
OVERWRITE_KINDS = ["clean", "sigterm", "fail"]


def draw_reruns(seed, index, case, limits):
    """Whether the case is also run on two MPI ranks and rerun with --overwrite (which kind),
    each for about 15 % of cases, from a stream of its own: the draws above, and so the cases
    of earlier seeds, stay as they were."""
    r = random.Random(f"combination-sweep-reruns:{seed}:{index}")
    case.mpi = limits.mpi and r.random() < 0.15
    if r.random() < 0.15:
        case.overwrite = r.choice(OVERWRITE_KINDS)


def draw_case(seed, index, limits=FULL):
    r = random.Random(f"combination-sweep:{seed}:{index}")
    k = {}
    draw_material(r, k)
    path = r.choices(["none", "ramp", "sine", "table"], [0.08, 0.22, 0.4, 0.3])[0]
    wear = path in ("sine", "table") and r.random() < 0.4
    costly = r.random() < 0.2
    n = draw_grid(r, k, wear, costly, limits)
    nx, ny = k.get("grid.nx", n), k.get("grid.ny", n)
    files = {}
    scales = draw_surface(r, k, files, nx, ny)
    integ = None
    if wear:
        integ = r.choice(["erk", "dirk", "arkode", "cycle"])
    mu_low = draw_friction(r, k, integ)
    if "friction.mu_final" in k:
        # X moves mu most of the way within a cycle or two: a dissipation density of p0 U*,
        # or a slip path of U*.
        dissipation = k["friction.evolution"] == "dissipation"
        k["friction.scale"] = scales.p0 * scales.u_star if dissipation else scales.u_star
    k["load.path"] = path
    notes = draw_load(r, k, files, scales, mu_low, path, wear)
    if "two_d" in notes and wear and r.random() < 0.8:
        integ = "cycle"  # 2-D motion with an ODE integrator is a documented refusal
    draw_solver(r, k, n, limits)
    if wear:
        draw_wear(r, k, scales, integ, limits)
    draw_output(r, k, wear)
    mode, arg = draw_mode(r, wear)
    case = Case(index, k, files, mode, arg, notes)
    draw_steps(seed, index, case, max(nx, ny))
    draw_reruns(seed, index, case, limits)
    return case
