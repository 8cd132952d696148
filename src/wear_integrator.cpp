// Wear integrators over the cycle count N: cycle by cycle (reference) and SUNDIALS ARKODE
// (explicit ERKStep; implicit ARKStep SDIRK + SPGMR). See wear_integrator.hpp.
#include "fretbem/wear_integrator.hpp"

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

#include "fretbem/errors.hpp"
#include "fretbem/wear_preconditioner.hpp"

namespace fretbem {

double explicit_step_cap(const Model& model, double max_slip) {
  const double k = model.wear->archard_equivalent(model.scenario.material.mu);
  const double K_max = 1.7 * model.scenario.material.E_star() / model.scenario.grid.h;
  if (!(max_slip > 0.0)) return INFINITY;  // nothing slips: no wear, no bound
  return 1.0 / (k * max_slip * K_max);
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

void keep(WearReport& rep, WearCycle c, WearLog* log, double simulated) {
  if (log) log->cycle(c, simulated);
  c.rate = Field();
  rep.history.push_back(std::move(c));
}

// Reference: cycle after cycle, tractions carried, each cycle's wear applied before the next.
WearReport integrate_cycles(Model& model, WearCycles& cyc, WearLog* log) {
  WearReport rep;
  const double N_end = model.scenario.wear.cycles;
  const auto snaps = snapshot_cycles(N_end);
  std::size_t next_snap = 0;
  cyc.start();
  for (double N = 0.0; N <= N_end; N += 1.0) {
    WearCycle c = cyc.carried(N);
    if (log && next_snap < snaps.size() && snaps[next_snap] <= N) {
      log->snapshot(N, model.surface0 - model.surface, cyc.pressure());
      ++next_snap;
    }
    if (N < N_end) cyc.apply(c.rate);  // the last cycle observes the final surface
    keep(rep, std::move(c), log, cyc.simulated());
  }
  rep.worn = model.surface0 - model.surface;
  rep.N = N_end;
  rep.simulated_cycles = cyc.simulated();
  rep.rhs_evaluations = cyc.evaluations();
  rep.steps = long(N_end);
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
  double step_max_slip = 0.0;  // largest slip per cycle seen in the current integrator step
  std::exception_ptr error;
  // Implicit mode: the last evaluation at an iterate (not a Jacobian probe) linearises the
  // Newton matrix (WearPreconditioner).
  std::unique_ptr<WearPreconditioner> pre;
  bool probing = false;
  Field base_pressure, base_rate;
  long base_generation = 0, linearised_generation = -1;
};

// dW/dN = w(z0 - W): one steady cycle on the current surface per evaluation. Exceptions
// cannot cross the C library: kept and rethrown after ARKODE returns.
int wear_rhs(realtype N, N_Vector y, N_Vector ydot, void* user) {
  auto& d = *static_cast<OdeData*>(user);
  try {
    const Grid& g = d.model.scenario.grid;
    const Field W = Eigen::Map<const Field>(N_VGetArrayPointer(y), g.nx, g.ny);
    WearCycle c = d.cyc.steady(N, W);
    Eigen::Map<Field>(N_VGetArrayPointer(ydot), g.nx, g.ny) = c.rate;
    if (d.pre && !d.probing) {
      d.base_pressure = d.cyc.pressure();
      d.base_rate = c.rate;
      ++d.base_generation;
    }
    d.step_max_slip = std::max(d.step_max_slip, c.max_slip);
    keep(d.rep, std::move(c), d.log, d.cyc.simulated());
    return 0;
  } catch (...) {
    d.error = std::current_exception();
    return -1;
  }
}

void silent(int, const char*, const char*, char*, void*) {}

// Newton matrix P = I - gamma J linearised at the last evaluated iterate (frozen slip).
int wear_psetup(realtype, N_Vector, N_Vector, booleantype, booleantype* jcur, realtype,
                void* user) {
  auto& d = *static_cast<OdeData*>(user);
  d.pre->setup(d.base_pressure, d.base_rate);
  *jcur = SUNTRUE;
  return 0;
}

int wear_psolve(realtype, N_Vector, N_Vector, N_Vector r, N_Vector z, realtype gamma, realtype, int,
                void* user) {
  auto& d = *static_cast<OdeData*>(user);
  try {
    const Grid& g = d.model.scenario.grid;
    Field x;
    d.pre->solve(Eigen::Map<const Field>(N_VGetArrayPointer(r), g.nx, g.ny), gamma, x);
    Eigen::Map<Field>(N_VGetArrayPointer(z), g.nx, g.ny) = x;
    return 0;
  } catch (...) {
    d.error = std::current_exception();
    return -1;
  }
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
  const double sigma = (d.model.scenario.wear.rtol * W_rms + d.model.scenario.wear.atol) / vnorm;
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
  long solves = 0;
};

SUNLinearSolver_Type frozen_type(SUNLinearSolver) {
  return SUNLINEARSOLVER_MATRIX_EMBEDDED;
}

int frozen_setup(SUNLinearSolver S, SUNMatrix) {
  auto& c = *static_cast<FrozenSlipContent*>(S->content);
  c.data->pre->setup(c.data->base_pressure, c.data->base_rate);
  return 0;
}

int frozen_solve(SUNLinearSolver S, SUNMatrix, N_Vector x, N_Vector b, realtype) {
  auto& c = *static_cast<FrozenSlipContent*>(S->content);
  OdeData& d = *c.data;
  try {
    realtype gamma = 0.0;
    ARKStepGetCurrentGamma(c.arkode, &gamma);
    const Grid& g = d.model.scenario.grid;
    if (d.linearised_generation != d.base_generation) {
      d.pre->setup(d.base_pressure, d.base_rate);
      d.linearised_generation = d.base_generation;
    }
    Field out;
    d.pre->solve(Eigen::Map<const Field>(N_VGetArrayPointer(b), g.nx, g.ny), gamma, out);
    Eigen::Map<Field>(N_VGetArrayPointer(x), g.nx, g.ny) = out;
    ++c.solves;
    return 0;
  } catch (...) {
    d.error = std::current_exception();
    return SUNLS_PSOLVE_FAIL_UNREC;
  }
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
  S->content = new FrozenSlipContent{&d, arkode, 0};
  S->ops->gettype = frozen_type;
  S->ops->setup = frozen_setup;
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
  void stats(long& steps, long& fails) {
    if (implicit)
      ARKStepGetNumSteps(mem, &steps), ARKStepGetNumErrTestFails(mem, &fails);
    else
      ERKStepGetNumSteps(mem, &steps), ERKStepGetNumErrTestFails(mem, &fails);
  }
};

void check(int flag, const char* what) {
  if (flag < 0)
    throw SolverError(std::string("ARKODE ") + what + " failed (flag " + std::to_string(flag) +
                      ")");
}

// SDIRK order 2 (ARKODE's default 2nd-order DIRK table). Newton (wear.newton):
//  - frozen (default): modified Newton with the frozen-slip Newton matrix solved exactly
//    (FrozenSlip linear solver): one simulated cycle per Newton iteration;
//  - krylov: Jacobian-free Newton–Krylov, SPGMR with finite-difference Jacobian-vector
//    products of the wear map (one simulated cycle each), right-preconditioned by the same
//    frozen-slip matrix.
// Measured (docs/wear.md): krylov needed 4229 simulated cycles to N = 1e6 at n = 64 where frozen
// needed 516 and the explicit method 2011; without the preconditioner, krylov is worse still.
// The map is only piecewise smooth (contact and slip sets change), so low order.
void create_implicit(Integrator& it, N_Vector y, SUNContext ctx, OdeData& d, double h0) {
  const WearSpec& w = d.model.scenario.wear;
  it.mem = ARKStepCreate(nullptr, wear_rhs, 0.0, y, ctx);
  if (!it.mem) throw SolverError("ARKODE: ARKStepCreate failed");
  check(ARKStepSStolerances(it.mem, w.rtol, w.atol), "tolerances");
  check(ARKStepSetUserData(it.mem, &d), "user data");
  check(ARKStepSetErrHandlerFn(it.mem, silent, nullptr), "error handler");
  check(ARKStepSetOrder(it.mem, 2), "order");
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
  check(ERKStepSStolerances(it.mem, w.rtol, w.atol), "tolerances");
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

// wear.integrator = arkode: the explicit method while the run is short against its stability
// cap, the implicit one past it. Measured (docs/wear.md): explicit wins at N_end / cap = 9 (n = 32,
// 500 cycles: 54 vs 140 simulated cycles) and 16 (n = 64, 1e4: 35 vs 191); implicit wins at 360
// (n = 32, 2e4: 436 vs 755) and 1600 (n = 64, 1e6: 516 vs 2011).
constexpr double kImplicitPastCaps = 100.0;

WearReport integrate_ode(Model& model, WearCycles& cyc, WearLog* log, WearIntegrator kind) {
  WearReport rep;
  const Grid& g = model.scenario.grid;
  const double N_end = model.scenario.wear.cycles;
  SunContext sun;
  N_Vector y = N_VNew_Serial(sunindextype(g.nx) * g.ny, sun.ctx);
  if (!y) throw SolverError("SUNDIALS: no vector");
  std::unique_ptr<_generic_N_Vector, void (*)(N_Vector)> y_owner(y, N_VDestroy);
  N_VConst(0.0, y);
  OdeData d{model, cyc, log, rep};
  cyc.start();
  // A first steady cycle on the unworn surface: the N = 0 row, snapshot and stability cap.
  WearCycle c0 = cyc.steady(0.0, Field::Zero(g.nx, g.ny));
  if (log) log->snapshot(0.0, Field::Zero(g.nx, g.ny), cyc.pressure());
  const double cap = explicit_step_cap(model, c0.max_slip);
  keep(rep, std::move(c0), log, cyc.simulated());
  const bool implicit = kind == WearIntegrator::dirk ||
                        (kind == WearIntegrator::arkode && N_end > kImplicitPastCaps * cap);
  rep.implicit = implicit;
  if (implicit)
    d.pre = std::make_unique<WearPreconditioner>(*model.half_space,
                                                 model.path.steps.front().normal.force_control);
  Integrator it;
  it.implicit = implicit;
  create(it, y, sun.ctx, d, std::min(cap, N_end));
  double t = 0.0;
  // Steps run free of the snapshot times (a stop at each would cut the steps to the geometric
  // sequence 1, 2, 5, ...); the worn depth there comes from the integrator's interpolant.
  const auto snaps = snapshot_cycles(N_end);
  std::size_t next = 1;
  N_Vector ys = N_VClone(y);
  std::unique_ptr<_generic_N_Vector, void (*)(N_Vector)> ys_owner(ys, N_VDestroy);
  check(it.stop(N_end), "stop time");
  while (t < N_end) {
    d.step_max_slip = 0.0;
    const int flag = it.evolve(N_end, y, &t);
    if (d.error) std::rethrow_exception(d.error);
    check(flag, "step");
    if (!implicit) check(it.max_step(explicit_step_cap(model, d.step_max_slip)), "max step");
    for (; log && next + 1 < snaps.size() && snaps[next] <= t; ++next) {
      check(it.dky(snaps[next], ys), "interpolation");
      const Field W = Eigen::Map<const Field>(N_VGetArrayPointer(ys), g.nx, g.ny);
      log->snapshot(snaps[next], W, cyc.pressure_on(W));
    }
  }
  // The final surface: one more steady cycle to observe it (its wear is not applied).
  rep.worn = Eigen::Map<const Field>(N_VGetArrayPointer(y), g.nx, g.ny);
  WearCycle c = cyc.steady(N_end, rep.worn);
  if (log) log->snapshot(N_end, rep.worn, cyc.pressure());
  keep(rep, std::move(c), log, cyc.simulated());
  model.surface = model.surface0 - rep.worn;
  it.stats(rep.steps, rep.rejected);
  if (implicit) {
    ARKStepGetNumNonlinSolvIters(it.mem, &rep.newton_iterations);
    ARKStepGetNumNonlinSolvConvFails(it.mem, &rep.newton_failures);
    ARKStepGetNumLinIters(it.mem, &rep.krylov_iterations);
    rep.inner_iterations = d.pre->iterations();
  }
  rep.N = N_end;
  rep.simulated_cycles = cyc.simulated();
  rep.rhs_evaluations = cyc.evaluations();
  return rep;
}

}  // namespace

WearReport integrate_wear(Model& model, WearCycles& cycles, WearLog* log) {
  if (!model.wear) throw InputError("wear.law: none (no wear to integrate)");
  switch (model.scenario.wear.integrator) {
    case WearIntegrator::cycle:
      return integrate_cycles(model, cycles, log);
    case WearIntegrator::arkode:
    case WearIntegrator::erk:
    case WearIntegrator::dirk:
      return integrate_ode(model, cycles, log, model.scenario.wear.integrator);
  }
  throw InputError("wear.integrator: unknown");
}

}  // namespace fretbem
