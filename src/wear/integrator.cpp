// Wear integrators over the cycle count N: cycle by cycle (reference) and SUNDIALS ARKODE
// (explicit ERKStep; implicit ARKStep TR-BDF2). See wear_integrator.hpp.
#include "fretbem/wear/integrator.hpp"

#include <arkode/arkode_arkstep.h>
#include <arkode/arkode_erkstep.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sunlinsol/sunlinsol_spgmr.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <exception>
#include <memory>
#include <utility>

#include "fretbem/core/errors.hpp"
#include "fretbem/core/fingerprint.hpp"
#include "fretbem/core/format.hpp"
#include "fretbem/wear/cost_estimate.hpp"
#include "fretbem/wear/preconditioner.hpp"

namespace fretbem {

double explicit_step_cap(const Model& model, double max_slip) {
  const double k = model.wear->archard_equivalent(model.scenario.material.mu);
  const double K_max = 1.7 * model.scenario.material.E_star() / model.scenario.grid.h;
  if (!(max_slip > 0.0)) return INFINITY;  // nothing slips: no wear, no bound
  return 1.0 / (k * max_slip * K_max);
}

// The explicit step stays at the cap in shakedown (the slipping nodes at the stick edge keep
// the stiff modes), so erk costs a few simulated cycles per cap: measured 6303 for N = 5e4
// at n = 32, Q = 0.3 mu P, k = 2e-11 (tools/bench/wear_sweep.py, over N/10), where arkode
// (-> dirk) took 81.6 for N = 1e5 at k = 1e-11. A user's explicit choice is kept (it is the method
// asked for, e.g. to compare against), and said instead of silently switched.
std::string explicit_cap_warning(const WearSpec& wear, double cap) {
  const double N = wear.cycles;
  if (wear.integrator != WearIntegrator::erk || !(N > kImplicitPastCaps * cap)) return {};
  return "warning: wear.integrator = erk: explicit steps are capped by stability at " +
         format_printf("%.3g", cap) +
         " cycles on the unworn surface (wear.cycles = " + format_number(N) + " is " +
         format_printf("%.3g", N / cap) +
         " caps; each step costs two wear-map evaluations of 1.25 simulated cycles); past " +
         format_printf("%g", kImplicitPastCaps) +
         " caps wear.integrator = dirk (implicit, not capped), or arkode (the default, which "
         "picks dirk there), simulates fewer cycles";
}

// Cost guard: an integrator step is worth its simulated cycles only when it covers at least
// kStepWorth times as many real cycles; otherwise the run simulates a stretch of cycles one by
// one (the cycle-mode arithmetic on the steady loop), at least kMinStretch long and doubling
// while the integrator stays unprofitable, so the integrator's wasted trials stay a
// geometrically bounded fraction of the cycles simulated.
constexpr double kStepWorth = 2.0;
constexpr double kMinStretch = 8.0;

bool runs_implicit(WearIntegrator kind, double N, double cap, double evaluation_cycles) {
  if (kind == WearIntegrator::dirk) return true;
  if (kind != WearIntegrator::arkode) return false;
  return N > kImplicitPastCaps * cap || cap < kStepWorth * 2.0 * evaluation_cycles;
}

std::vector<double> snapshot_cycles(double N_end) {
  std::vector<double> out{0.0};
  for (double decade = 1.0; decade < N_end; decade *= 10.0)
    for (double m : {1.0, 2.0, 5.0})
      if (m * decade < N_end) out.push_back(m * decade);
  out.push_back(N_end);
  return out;
}

namespace {

void keep(WearReport& rep, WearCycle c, WearLog* log) {
  if (log) log->cycle(c);
  c.rate = Field();
  rep.history.push_back(std::move(c));
}

// Reference: cycle after cycle, tractions carried, each cycle's wear applied before the next.
// A checkpoint after every cycle whose wear was applied (the last one only observes).
WearReport integrate_cycles(Model& model, WearCycles& cyc, WearLog* log,
                            const WearCheckpoint* resume, long max_steps) {
  WearReport rep;
  const double N_end = model.scenario.wear.cycles;
  const auto snaps = snapshot_cycles(N_end);
  std::size_t next_snap = 0;
  double N0 = 0.0;
  long taken = 0;
  if (resume) {
    N0 = resume->N, next_snap = std::size_t(resume->next_snapshot);
    cyc.resume(resume->counters);
  } else {
    cyc.start();
  }
  if (log && !resume) log->expect(N_end + 1.0, N_end + 1.0);  // cycles 0..N_end
  for (double N = N0; N <= N_end; N += 1.0) {
    WearCycle c = cyc.carried(N);
    if (log && next_snap < snaps.size() && snaps[next_snap] <= N) {
      log->snapshot(N, model.surface0 - model.surface, cyc.pressure(), true);
      ++next_snap;
    }
    if (N < N_end) cyc.apply(c.rate);  // the last cycle observes the final surface
    c.accepted = true;
    keep(rep, std::move(c), log);
    if (N >= N_end) break;
    if (log) {
      WearCheckpoint at;
      at.N = N + 1.0;
      at.worn = model.surface0 - model.surface;
      at.counters = cyc.counters();
      at.steps = long(N) + 1;
      at.next_snapshot = long(next_snap);
      log->step_done(at);
    }
    if ((max_steps >= 0 && ++taken >= max_steps) || (log && log->stop_requested())) {
      rep.stopped = true;
      rep.N = N + 1.0;
      break;
    }
  }
  rep.worn = model.surface0 - model.surface;
  rep.cycle_by_cycle = true;
  if (!rep.stopped) rep.N = N_end;
  rep.simulated_cycles = cyc.simulated();
  rep.rhs_evaluations = cyc.evaluations();
  rep.steps = long(rep.N);
  return rep;
}

// --- ARKODE ------------------------------------------------------------------------------

struct SunContext {
  SUNContext ctx = nullptr;
  SunContext() {
    if (SUNContext_Create(nullptr, &ctx) != 0) throw SolverError("SUNDIALS: no context");
  }
  ~SunContext() { SUNContext_Free(&ctx); }
};

struct OdeData {
  OdeData(Model& m, WearCycles& c, WearLog* l, WearReport& r) : model(m), cyc(c), log(l), rep(r) {}
  Model& model;
  WearCycles& cyc;
  WearLog* log;
  WearReport& rep;
  double atol = 0.0;           // absolute tolerance on W (m): wear.atol, or rtol x indentation
  double step_max_slip = 0.0;  // largest slip per cycle seen in the current integrator step
  std::exception_ptr error;
  // Implicit mode: the last evaluation at an iterate (not a Jacobian probe) linearises the
  // Newton matrix (WearPreconditioner).
  std::unique_ptr<WearPreconditioner> pre;
  bool probing = false;
  Field base_pressure, base_rate;
  long base_generation = 0, linearised_generation = -1;
};

// The fingerprint of W identifies the evaluations made on an accepted state without keeping a
// copy of W per evaluation (a collision needs two different worn-depth fields with the same
// 64-bit value).
std::uint64_t fingerprint(const Eigen::Ref<const Field>& W) {
  Fingerprint f;
  f.add_bytes(W.data(), std::size_t(W.size()) * sizeof(double));
  return f.value();
}

// dW/dN = w(z0 - W): one steady cycle on the current surface per evaluation. Exceptions
// cannot cross the C library: kept and rethrown after ARKODE returns.
int wear_rhs(realtype N, N_Vector y, N_Vector ydot, void* user) {
  auto& d = *static_cast<OdeData*>(user);
  try {
    const Grid& g = d.model.scenario.grid;
    // Worn depth is never negative; an implicit method's Newton iterates may overshoot below
    // zero (material added), which would raise a node above the unworn surface.
    const Field W = Eigen::Map<const Field>(N_VGetArrayPointer(y), g.nx, g.ny).max(0.0);
    WearCycle c = d.cyc.steady(N, W);
    Eigen::Map<Field>(N_VGetArrayPointer(ydot), g.nx, g.ny) = c.rate;
    if (d.pre && !d.probing) {
      d.base_pressure = d.cyc.pressure();
      d.base_rate = c.rate;
      ++d.base_generation;
    }
    d.step_max_slip = std::max(d.step_max_slip, c.max_slip);
    c.worn_hash = fingerprint(W);
    // Logged once the step is done and its accepted state known (flush_step).
    keep(d.rep, std::move(c), nullptr);
    return 0;
  } catch (...) {
    d.error = std::current_exception();
    return -1;
  }
}

void silent(int, const char*, const char*, char*, void*) {}

// x = P^-1 b, P = I - gamma J~ the frozen-slip Newton matrix, linearised at the latest
// evaluated iterate (relinearised only when a new iterate has been evaluated since). Shared by
// the Krylov preconditioner and the matrix-embedded linear solver. Exceptions are kept for
// rethrow after ARKODE returns.
int newton_matrix_solve(OdeData& d, N_Vector b, N_Vector x, double gamma) {
  try {
    if (d.linearised_generation != d.base_generation) {
      d.pre->setup(d.base_pressure, d.base_rate);
      d.linearised_generation = d.base_generation;
    }
    const Grid& g = d.model.scenario.grid;
    Field out;
    d.pre->solve(Eigen::Map<const Field>(N_VGetArrayPointer(b), g.nx, g.ny), gamma, out);
    Eigen::Map<Field>(N_VGetArrayPointer(x), g.nx, g.ny) = out;
    return 0;
  } catch (...) {
    d.error = std::current_exception();
    return -1;
  }
}

int wear_psetup(realtype, N_Vector, N_Vector, booleantype, booleantype* jcur, realtype, void*) {
  *jcur = SUNTRUE;  // the matrix is relinearised in the solve, at the latest iterate
  return 0;
}

int wear_psolve(realtype, N_Vector, N_Vector, N_Vector r, N_Vector z, realtype gamma, realtype, int,
                void* user) {
  return newton_matrix_solve(*static_cast<OdeData*>(user), r, z, gamma);
}

// J v by a forward difference of the wear map, [w(W + sigma v) - w(W)] / sigma, with sigma
// scaling v to unit weighted-RMS norm (ARKODE's own choice), marked as a probe so that it does
// not become the linearisation point of the preconditioner.
int wear_jtimes(N_Vector v, N_Vector Jv, realtype N, N_Vector y, N_Vector fy, void* user,
                N_Vector tmp) {
  auto& d = *static_cast<OdeData*>(user);
  const double vnorm = std::sqrt(N_VDotProd(v, v) / double(N_VGetLength(v)));
  if (vnorm == 0.0) {
    N_VConst(0.0, Jv);
    return 0;
  }
  const double W_rms = std::sqrt(N_VDotProd(y, y) / double(N_VGetLength(y)));
  const double sigma = (d.model.scenario.wear.rtol * W_rms + d.atol) / vnorm;
  N_VLinearSum(1.0, y, sigma, v, tmp);
  d.probing = true;
  const int flag = wear_rhs(N, tmp, Jv, user);
  d.probing = false;
  if (flag != 0) return flag;
  N_VLinearSum(1.0 / sigma, Jv, -1.0 / sigma, fy, Jv);
  return 0;
}

// A matrix-embedded SUNLinearSolver: the Newton correction of an implicit stage from the
// frozen-slip Newton matrix, x = P^-1 b with P = I - gamma J~ (WearPreconditioner), linearised
// at the latest evaluated iterate. One simulated cycle per Newton iteration (the residual), no
// Jacobian-vector probes: a modified Newton iteration whose contraction rate is that of the
// neglected slip sensitivity.
struct FrozenSlipContent {
  OdeData* data = nullptr;
  void* arkode = nullptr;
};

SUNLinearSolver_Type frozen_type(SUNLinearSolver) {
  return SUNLINEARSOLVER_MATRIX_EMBEDDED;
}

int frozen_solve(SUNLinearSolver S, SUNMatrix, N_Vector x, N_Vector b, realtype) {
  auto& c = *static_cast<FrozenSlipContent*>(S->content);
  realtype gamma = 0.0;
  ARKStepGetCurrentGamma(c.arkode, &gamma);
  return newton_matrix_solve(*c.data, b, x, gamma) == 0 ? 0 : SUNLS_PSOLVE_FAIL_UNREC;
}

int frozen_free(SUNLinearSolver S) {
  delete static_cast<FrozenSlipContent*>(S->content);
  S->content = nullptr;
  SUNLinSolFreeEmpty(S);
  return 0;
}

SUNLinearSolver frozen_slip_solver(OdeData& d, void* arkode, SUNContext ctx) {
  SUNLinearSolver S = SUNLinSolNewEmpty(ctx);
  if (!S) throw SolverError("SUNDIALS: no linear solver");
  S->content = new FrozenSlipContent{&d, arkode};
  S->ops->gettype = frozen_type;
  S->ops->solve = frozen_solve;
  S->ops->free = frozen_free;
  return S;
}

// The two ARKODE steppers behind one face.
struct Integrator {
  void* mem = nullptr;
  SUNLinearSolver ls = nullptr;
  bool implicit = false;
  ~Integrator() {
    if (implicit)
      ARKStepFree(&mem);
    else
      ERKStepFree(&mem);
    if (ls) SUNLinSolFree(ls);
  }
  int stop(double t) { return implicit ? ARKStepSetStopTime(mem, t) : ERKStepSetStopTime(mem, t); }
  int max_step(double h) {
    return implicit ? ARKStepSetMaxStep(mem, h) : ERKStepSetMaxStep(mem, h);
  }
  int evolve(double tout, N_Vector y, double* t) {
    return implicit ? ARKStepEvolve(mem, tout, y, t, ARK_ONE_STEP)
                    : ERKStepEvolve(mem, tout, y, t, ARK_ONE_STEP);
  }
  int dky(double t, N_Vector y) {
    return implicit ? ARKStepGetDky(mem, t, 0, y) : ERKStepGetDky(mem, t, 0, y);
  }
  // Restart at (t, y) with a first step h (resume): options are kept, the step-size
  // controller's history is not.
  int reset(double t, N_Vector y, double h) {
    const int f = implicit ? ARKStepReset(mem, t, y) : ERKStepReset(mem, t, y);
    if (f < 0) return f;
    return implicit ? ARKStepSetInitStep(mem, h) : ERKStepSetInitStep(mem, h);
  }
  double next_step() {
    double h = 0.0;
    implicit ? ARKStepGetCurrentStep(mem, &h) : ERKStepGetCurrentStep(mem, &h);
    return h;
  }
  void stats(long& steps, long& fails) {
    if (implicit)
      ARKStepGetNumSteps(mem, &steps), ARKStepGetNumErrTestFails(mem, &fails);
    else
      ERKStepGetNumSteps(mem, &steps), ERKStepGetNumErrTestFails(mem, &fails);
  }
};

// A failed ARKODE call as one line a user can act on ("ARKODE step failed
// (flag -22)" named nothing): the call, the wear cycle N when known, SUNDIALS' name of the
// flag, and the keys that steer the integrator.
void check(int flag, const char* what, double N = -1.0) {
  if (flag >= 0) return;
  char* name = ARKStepGetReturnFlagName(flag);  // malloc'ed by SUNDIALS
  std::string msg = std::string("wear integrator (ARKODE): ") + what + " failed";
  if (N >= 0.0) msg += " at wear cycle N = " + format_count(N);
  msg += std::string(": ") + (name ? name : "unknown flag") + " (flag " + std::to_string(flag) +
         "); check wear.coefficient and wear.cycles, or try wear.integrator = cycle or other "
         "wear.rtol / wear.atol";
  std::free(name);
  throw SolverError(msg);
}

// Implicit method: TR-BDF2 (ARKODE_TRBDF2_3_3_2): an ESDIRK of order 2 with an explicit first
// stage (the wear map at the accepted state, which is that state's row), L-stable and stiffly
// accurate (its solution is its last stage, R(inf) = 0), with an embedded order-3 error
// estimate. SDIRK-2-1-2 has R(inf) = -1/2 and a backward-Euler embedding
// whose error estimate is a newly touching node's whole depth in ~10 % of steps.
// Measured on a partial-slip sphere (n = 64, to N = 5e4, the same tolerances and
// cost guard): TR-BDF2 682 simulated cycles to the end state; SDIRK-2-1-2 ~800 by N ~ 4000;
// ESDIRK ARK324L2SA (order 3) 1123 by N ~ 4450 (docs/wear.md). The wear map is only piecewise
// smooth (contact nodes enter the worn annulus in groups), so order 2 is enough.
// Newton (wear.newton):
//  - frozen (default): modified Newton with the frozen-slip Newton matrix solved exactly
//    (FrozenSlip linear solver): one simulated cycle per Newton iteration;
//  - krylov: Jacobian-free Newton–Krylov, SPGMR with finite-difference Jacobian-vector
//    products of the wear map (one simulated cycle each), right-preconditioned by the same
//    frozen-slip matrix.
// Measured (docs/wear.md): krylov needed 4229 simulated cycles to N = 1e6 at n = 64 where frozen
// needed 516 and the explicit method 2011; without the preconditioner, krylov is worse still.
void create_implicit(Integrator& it, N_Vector y, SUNContext ctx, OdeData& d, double h0) {
  const WearSpec& w = d.model.scenario.wear;
  it.mem = ARKStepCreate(nullptr, wear_rhs, 0.0, y, ctx);
  if (!it.mem) throw SolverError("ARKODE: ARKStepCreate failed");
  check(ARKStepSStolerances(it.mem, w.rtol, d.atol), "tolerances");
  check(ARKStepSetUserData(it.mem, &d), "user data");
  check(ARKStepSetErrHandlerFn(it.mem, silent, nullptr), "error handler");
  check(ARKStepSetTableNum(it.mem, ARKODE_TRBDF2_3_3_2, ARKODE_ERK_NONE), "method");
  check(ARKStepSetMaxNumSteps(it.mem, 100000), "max steps");
  check(ARKStepSetInitStep(it.mem, h0), "first step");
  if (w.newton == WearNewton::frozen) {
    it.ls = frozen_slip_solver(d, it.mem, ctx);
    check(ARKStepSetLinearSolver(it.mem, it.ls, nullptr), "linear solver");
    // The stage derivative from the converged Newton iterate instead of one more simulated
    // cycle at it, and the predictor of maximum order: 770 -> 516 simulated cycles to 1e6
    // (n = 64, docs/wear.md).
    check(ARKStepSetDeduceImplicitRhs(it.mem, SUNTRUE), "deduced stage derivative");
    check(ARKStepSetPredictorMethod(it.mem, 1), "predictor");
    return;
  }
  it.ls = SUNLinSol_SPGMR(y, SUN_PREC_RIGHT, 5, ctx);
  check(ARKStepSetLinearSolver(it.mem, it.ls, nullptr), "linear solver");
  check(ARKStepSetPreconditioner(it.mem, wear_psetup, wear_psolve), "preconditioner");
  check(ARKStepSetJacTimes(it.mem, nullptr, wear_jtimes), "Jacobian-vector product");
}

void create(Integrator& it, N_Vector y, SUNContext ctx, OdeData& d, double h_cap) {
  const WearSpec& w = d.model.scenario.wear;
  // ARKODE's own first-step estimate starts orders of magnitude too small on a zero worn
  // depth; start from the stability cap, or a hundredth of the run.
  const double h0 = std::min(h_cap, std::max(1.0, 0.01 * w.cycles));
  if (it.implicit) return create_implicit(it, y, ctx, d, h0);
  it.mem = ERKStepCreate(wear_rhs, 0.0, y, ctx);
  if (!it.mem) throw SolverError("ARKODE: ERKStepCreate failed");
  check(ERKStepSStolerances(it.mem, w.rtol, d.atol), "tolerances");
  check(ERKStepSetUserData(it.mem, &d), "user data");
  check(ERKStepSetErrHandlerFn(it.mem, silent, nullptr), "error handler");
  check(ERKStepSetMaxNumSteps(it.mem, 100000), "max steps");
  check(ERKStepSetMaxStep(it.mem, h_cap), "max step");
  // Heun–Euler 2(1): two wear-map evaluations per step. Each evaluation is a simulated cycle,
  // the accuracy asked for is loose (rtol ~ 1e-3) and the step is capped by stability anyway,
  // so a higher order buys little for its extra stages.
  check(ERKStepSetTableNum(it.mem, ARKODE_HEUN_EULER_2_1_2), "method");
  check(ERKStepSetInitStep(it.mem, h0), "first step");
}

// Logs the rows of one integrator step (evaluations from rep.history[first] on) with their
// accepted flag: an evaluation is accepted when it ran on the state before or after the step
// (W and N equal) and that state has no accepted row yet, so N increases over accepted rows.
// `last` (N, fingerprint) is the state with the latest accepted row; `final_state`: the state
// after the step is the final one, whose accepted row is the final observation instead.
void flush_step(WearReport& rep, std::size_t first, WearLog* log, double t0, std::uint64_t h0,
                double t1, std::uint64_t h1, bool final_state,
                std::pair<double, std::uint64_t>& last) {
  for (std::size_t k = first; k < rep.history.size(); ++k) {
    WearCycle& c = rep.history[k];
    const std::pair<double, std::uint64_t> key{c.N, c.worn_hash};
    const bool before = key == std::pair{t0, h0}, after = key == std::pair{t1, h1};
    c.accepted = (before || (after && !final_state)) && key != last;
    if (c.accepted) last = key;
    if (log) log->cycle(c);
  }
}

// The absolute tolerance on W (m): wear.atol when given (expert override), else rtol times the
// indentation of the unworn surface. A fixed metre value carried over from another scenario
// let nodes that just came into contact (W ~ 1e-10 m) set the step: 5757 simulated cycles to
// N = 5e4 at n = 64; the indentation is the depth scale of the end state (Popov:
// d_inf - d_0 is a fraction of d_0) and of gross-slip wear per integrator step.
// A given atol is held to wear.rtol's range relative to that depth scale (it is known only
// after the first normal solve, so `check` cannot refuse it).
double absolute_tolerance(const Model& model, WearCycles& cyc) {
  const WearSpec& w = model.scenario.wear;
  const double delta0 = std::abs(cyc.initial_indentation());
  if (w.atol <= 0.0) return w.rtol * delta0;
  if (delta0 > 0.0 &&
      !(w.atol >= kMinWearRelTolerance * delta0 && w.atol <= kMaxWearRelTolerance * delta0))
    throw InputError("wear.atol = " + format_number(w.atol) + " m is outside [" +
                     format_number(kMinWearRelTolerance) + ", " +
                     format_number(kMaxWearRelTolerance) + "] x the unworn indentation " +
                     format_number(delta0) +
                     " m: the error control would not hold the worn depth (or ARKODE fails); "
                     "leave wear.atol out to use wear.rtol x that indentation");
  return w.atol;
}

// N += L cycles one by one from (t, W): the steady cycle of W, then the physical history
// (tractions carried, each cycle's wear applied before the next). Every row is a point of the
// solution (accepted).
double cycle_stretch(WearCycles& cyc, WearReport& rep, WearLog* log, double t, Field& W, long L,
                     std::pair<double, std::uint64_t>& last) {
  for (long k = 0; k < L; ++k, t += 1.0) {
    WearCycle c = k == 0 ? cyc.steady(t, W) : cyc.continued(t);
    c.worn_hash = fingerprint(W);
    // The state the stretch starts from may have its accepted row already (the integrator
    // step's last evaluation).
    const std::pair<double, std::uint64_t> key{t, c.worn_hash};
    c.accepted = key != last;
    last = key;
    W += c.rate;
    if (k + 1 < L) cyc.apply(c.rate);
    keep(rep, std::move(c), log);
  }
  ++rep.stretches;
  rep.stretch_cycles += double(L);
  return t;
}

WearReport integrate_ode(Model& model, WearCycles& cyc, WearLog* log, WearIntegrator kind,
                         const WearCheckpoint* resume, long max_steps) {
  WearReport rep;
  const Grid& g = model.scenario.grid;
  const double N_end = model.scenario.wear.cycles;
  SunContext sun;
  N_Vector y = N_VNew_Serial(sunindextype(g.nx) * g.ny, sun.ctx);
  if (!y) throw SolverError("SUNDIALS: no vector");
  std::unique_ptr<_generic_N_Vector, void (*)(N_Vector)> y_owner(y, N_VDestroy);
  auto Wy = [&] { return Eigen::Map<Field>(N_VGetArrayPointer(y), g.nx, g.ny); };
  N_VConst(0.0, y);
  OdeData d{model, cyc, log, rep};
  double t = 0.0, cap = INFINITY;
  std::size_t first_snap = 1;
  long steps0 = 0, rejected0 = 0;
  if (resume) {
    Wy() = resume->worn;
    t = resume->N, cap = resume->h_max;
    first_snap = std::size_t(resume->next_snapshot);
    steps0 = resume->steps, rejected0 = resume->rejected;
    cyc.resume(resume->counters);
  } else {
    cyc.start();
    // A first steady cycle on the unworn surface: the N = 0 row, snapshot and stability cap.
    WearCycle c0 = cyc.steady(0.0, Field::Zero(g.nx, g.ny));
    c0.accepted = true;
    c0.worn_hash = fingerprint(Wy());
    if (log) log->snapshot(0.0, Field::Zero(g.nx, g.ny), cyc.pressure(), true);
    cap = explicit_step_cap(model, c0.max_slip);
    keep(rep, std::move(c0), log);
    if (const std::string w = explicit_cap_warning(model.scenario.wear, cap); log && !w.empty())
      log->warn(w);
  }
  d.atol = absolute_tolerance(model, cyc);
  // The state whose accepted row is out. A checkpoint is written before the state it holds
  // has a row (its row is the first evaluation of the next step), so a resumed run starts
  // with none (a resume row written with accepted = 0 would hide an accepted state).
  std::pair<double, std::uint64_t> last =
      resume ? std::pair{-1.0, std::uint64_t(0)} : std::pair{t, fingerprint(Wy())};
  // The cap of the unworn surface decides arkode's method; a resumed run keeps that choice.
  const bool implicit =
      resume ? kind != WearIntegrator::erk && (kind == WearIntegrator::dirk || resume->implicit)
             : runs_implicit(kind, N_end, cap, cyc.simulated());
  rep.implicit = implicit;
  if (log && !resume) {
    const SimulatedCycles e = expected_simulated_cycles(model.scenario, implicit, cap,
                                                        cyc.simulated(), rep.history.front());
    log->expect(e.low, e.high);
  }
  if (implicit)
    d.pre = std::make_unique<WearPreconditioner>(*model.half_space,
                                                 model.path.steps.front().normal.force_control);
  Integrator it;
  it.implicit = implicit;
  create(it, y, sun.ctx, d, std::min(cap, N_end));
  // A resumed run restarts a fresh integrator at (N, W) with the step it was about to try.
  // The explicit integrator restarts so after every step anyway (below): resuming repeats the
  // uninterrupted run. The implicit one loses its step-size and Newton history: close to,
  // not bit-identical with, the uninterrupted run (docs/wear.md).
  if (resume) check(it.reset(t, y, std::min(resume->h_next, N_end - t)), "restart");
  const auto snaps = snapshot_cycles(N_end);
  long taken = 0;
  double stretch = kMinStretch;
  bool stretched = false;  // the previous wear step was a stretch of cycles
  for (std::size_t i = first_snap; i < snaps.size() && !rep.stopped; ++i) {
    check(it.stop(snaps[i]), "stop time");
    while (t < snaps[i]) {
      d.step_max_slip = 0.0;
      const double t0 = t, sim0 = cyc.simulated();
      const std::uint64_t h0 = fingerprint(Wy());
      const std::size_t first = rep.history.size();
      const int flag = it.evolve(snaps[i], y, &t);
      if (d.error) std::rethrow_exception(d.error);
      check(flag, "step", t);
      if (!implicit) {
        cap = explicit_step_cap(model, d.step_max_slip);
        check(it.max_step(cap), "max step");
      }
      const bool final_state = t >= N_end;
      flush_step(rep, first, log, t0, h0, t, fingerprint(Wy()), final_state, last);
      if (final_state) break;
      // The explicit step obeys the new cap from its first attempt on.
      double h_next = implicit ? it.next_step() : std::min(it.next_step(), cap);
      // Cost guard (above): simulate cycles while the integrator is not cheaper.
      const bool unprofitable = kStepWorth * (cyc.simulated() - sim0) > t - t0;
      if (unprofitable) {
        stretch = stretched ? 2.0 * stretch : std::max(kMinStretch, cyc.simulated() - sim0);
        // Whole cycles to the snapshot; t may sit a rounding error below a whole number.
        const double eps = 1e-9 * std::max(1.0, snaps[i]);
        const long L = long(std::min(stretch, std::floor(snaps[i] - t + eps)));
        if (L >= 1) {
          Field W = Wy();
          t = cycle_stretch(cyc, rep, log, t, W, L, last);
          if (std::abs(t - snaps[i]) <= eps) t = snaps[i];
          Wy() = W;
        }
        stretched = L >= 1;
      } else {
        stretched = false;
      }
      if (t >= N_end) break;
      const bool snap = t >= snaps[i];
      if (log && snap) log->snapshot(t, Wy(), cyc.pressure_on(Wy()), false);
      long steps = 0, fails = 0;
      it.stats(steps, fails);
      if (!implicit || stretched) {
        // SUNDIALS 6.4 ERKStep treats a table with c_s = 1 as first-same-as-last and reuses
        // the last stage's f(t + h, y + h k1) as the next step's f(t_{n+1}, y_{n+1}): for
        // Heun–Euler (b = (1/2, 1/2) != a_2 = (1, 0)) one evaluation per step instead of two,
        // and not the method (y' = y, h = 0.1, 10 steps: 2.70838 instead of Heun's 2.71408;
        // measured with the installed 6.4.1). A restart at the accepted (t, y) makes ARKODE
        // evaluate f there — the correct first stage and the accepted row of the step — and
        // is exactly what a resumed run does, so resuming is the uninterrupted run. After a
        // stretch of cycles both integrators restart at its end.
        h_next = std::min(h_next, N_end - t);
        check(it.reset(t, y, h_next), "restart");
        check(it.stop(snaps[i]), "stop time");
      }
      if (log) {
        WearCheckpoint at;
        at.N = t;
        at.worn = Wy();
        at.h_next = h_next;
        at.h_max = cap;
        at.counters = cyc.counters();
        at.steps = steps0 + steps, at.rejected = rejected0 + fails;
        at.next_snapshot = long(snap ? i + 1 : i);
        at.implicit = implicit;
        log->step_done(at);
      }
      if ((max_steps >= 0 && ++taken >= max_steps) || (log && log->stop_requested())) {
        rep.stopped = true;
        break;
      }
    }
  }
  it.stats(rep.steps, rep.rejected);
  if (implicit) {
    ARKStepGetNumNonlinSolvIters(it.mem, &rep.newton_iterations);
    ARKStepGetNumNonlinSolvConvFails(it.mem, &rep.newton_failures);
    ARKStepGetNumLinIters(it.mem, &rep.krylov_iterations);
    rep.inner_iterations = d.pre->iterations();
  }
  rep.steps += steps0, rep.rejected += rejected0;
  rep.worn = Wy();
  rep.N = t;
  if (!rep.stopped) {
    // The final surface: one more steady cycle to observe it (its wear is not applied).
    WearCycle c = cyc.steady(N_end, rep.worn);
    c.accepted = true;
    if (log) log->snapshot(N_end, rep.worn, cyc.pressure(), true);
    keep(rep, std::move(c), log);
    rep.N = N_end;
  }
  model.surface = model.surface0 - rep.worn;
  rep.simulated_cycles = cyc.simulated();
  rep.rhs_evaluations = cyc.evaluations();
  return rep;
}

}  // namespace

Field indenter_worn(const Model& model, const Field& worn) {
  return model.scenario.wear.indenter_share * worn;
}

Field half_space_worn(const Model& model, const Field& worn) {
  return (1.0 - model.scenario.wear.indenter_share) * worn;
}

// Runs this short are simulated cycle by cycle whatever wear.integrator says: an ODE
// integrator cannot beat N + 1 simulated cycles there (its first steady cycle, one step per
// snapshot 1, 2, 5, 10, 20 of at least two evaluations each, and the final observation):
// measured at n = 32, Q = 0.6 mu P, k = 1e-11 (tools/bench/wear_sweep.py), arkode took 17.4
// simulated cycles for N = 10; see docs/wear.md for the crossover.
constexpr double kShortRun = 20.0;

WearReport integrate_wear(Model& model, WearCycles& cycles, WearLog* log,
                          const WearCheckpoint* resume, long max_steps) {
  if (!model.wear) throw InputError("wear.law: none (no wear to integrate)");
  const double N_end = model.scenario.wear.cycles;
  if (N_end <= kShortRun && N_end == std::floor(N_end))
    return integrate_cycles(model, cycles, log, resume, max_steps);
  switch (model.scenario.wear.integrator) {
    case WearIntegrator::cycle:
      return integrate_cycles(model, cycles, log, resume, max_steps);
    case WearIntegrator::arkode:
    case WearIntegrator::erk:
    case WearIntegrator::dirk:
      return integrate_ode(model, cycles, log, model.scenario.wear.integrator, resume, max_steps);
  }
  throw InputError("wear.integrator: unknown");
}

}  // namespace fretbem
