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
#include <exception>

#include "fretbem/errors.hpp"

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
  Model& model;
  WearCycles& cyc;
  WearLog* log;
  WearReport& rep;
  double step_max_slip = 0.0;  // largest slip per cycle seen in the current integrator step
  std::exception_ptr error;
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
    d.step_max_slip = std::max(d.step_max_slip, c.max_slip);
    keep(d.rep, std::move(c), d.log, d.cyc.simulated());
    return 0;
  } catch (...) {
    d.error = std::current_exception();
    return -1;
  }
}

void silent(int, const char*, const char*, char*, void*) {}

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
  // Restart at (t, y) with a first step h: options are kept, the step-size controller's
  // history is not.
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
  int stop(double t) { return implicit ? ARKStepSetStopTime(mem, t) : ERKStepSetStopTime(mem, t); }
  int max_step(double h) {
    return implicit ? ARKStepSetMaxStep(mem, h) : ERKStepSetMaxStep(mem, h);
  }
  int evolve(double tout, N_Vector y, double* t) {
    return implicit ? ARKStepEvolve(mem, tout, y, t, ARK_ONE_STEP)
                    : ERKStepEvolve(mem, tout, y, t, ARK_ONE_STEP);
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

void create(Integrator& it, N_Vector y, SUNContext ctx, OdeData& d, double h_cap) {
  const WearSpec& w = d.model.scenario.wear;
  if (it.implicit) {
    // SDIRK with Newton–Krylov: SPGMR, no preconditioner; ARKODE's default Jv is the
    // difference quotient [f(W + sigma v) - f(W)] / sigma, i.e. one simulated cycle per
    // Krylov iteration. The per-cycle map is only piecewise smooth (the contact and slip sets
    // change), so low order (2) and a modest Krylov space.
    it.mem = ARKStepCreate(nullptr, wear_rhs, 0.0, y, ctx);
    if (!it.mem) throw SolverError("ARKODE: ARKStepCreate failed");
    check(ARKStepSStolerances(it.mem, w.rtol, w.atol), "tolerances");
    check(ARKStepSetUserData(it.mem, &d), "user data");
    check(ARKStepSetErrHandlerFn(it.mem, silent, nullptr), "error handler");
    check(ARKStepSetOrder(it.mem, 2), "order");
    check(ARKStepSetMaxNumSteps(it.mem, 100000), "max steps");
    it.ls = SUNLinSol_SPGMR(y, SUN_PREC_NONE, 5, ctx);
    check(ARKStepSetLinearSolver(it.mem, it.ls, nullptr), "linear solver");
    return;
  }
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
  // ARKODE's own first-step estimate starts orders of magnitude too small on a zero worn
  // depth; start from the stability cap, or a hundredth of the run.
  check(ERKStepSetInitStep(it.mem, std::min(h_cap, std::max(1.0, 0.01 * w.cycles))), "first step");
}

WearReport integrate_ode(Model& model, WearCycles& cyc, WearLog* log, bool implicit) {
  WearReport rep;
  const Grid& g = model.scenario.grid;
  const double N_end = model.scenario.wear.cycles;
  SunContext sun;
  N_Vector y = N_VNew_Serial(sunindextype(g.nx) * g.ny, sun.ctx);
  if (!y) throw SolverError("SUNDIALS: no vector");
  std::unique_ptr<_generic_N_Vector, void (*)(N_Vector)> y_owner(y, N_VDestroy);
  N_VConst(0.0, y);
  OdeData d{model, cyc, log, rep, 0.0, nullptr};
  cyc.start();
  // A first steady cycle on the unworn surface: the N = 0 row, snapshot and stability cap.
  WearCycle c0 = cyc.steady(0.0, Field::Zero(g.nx, g.ny));
  if (log) log->snapshot(0.0, Field::Zero(g.nx, g.ny), cyc.pressure());
  const double cap = explicit_step_cap(model, c0.max_slip);
  keep(rep, std::move(c0), log, cyc.simulated());
  Integrator it;
  it.implicit = implicit;
  create(it, y, sun.ctx, d, std::min(cap, N_end));
  double t = 0.0;
  const auto snaps = snapshot_cycles(N_end);
  for (std::size_t i = 1; i < snaps.size(); ++i) {
    check(it.stop(snaps[i]), "stop time");
    while (t < snaps[i]) {
      d.step_max_slip = 0.0;
      const int flag = it.evolve(snaps[i], y, &t);
      if (d.error) std::rethrow_exception(d.error);
      check(flag, "step");
      if (implicit) continue;
      const double step_cap = explicit_step_cap(model, d.step_max_slip);
      check(it.max_step(step_cap), "max step");
      // SUNDIALS 6.4 ERKStep treats a table with c_s = 1 as first-same-as-last and reuses
      // the last stage's f(t + h, y + h k1) as the next step's f(t_{n+1}, y_{n+1}): for
      // Heun–Euler (b = (1/2, 1/2) != a_2 = (1, 0)) one evaluation per step instead of two,
      // and not the method (y' = y, h = 0.1, 10 steps: 2.70838 instead of Heun's 2.71408;
      // measured with the installed 6.4.1). A restart at the accepted (t, y) makes ARKODE
      // evaluate f there, the correct first stage. The explicit step obeys the new cap from
      // its first attempt on.
      check(it.reset(t, y, std::min(it.next_step(), step_cap)), "restart");
      check(it.stop(snaps[i]), "stop time");
    }
    const Field W = Eigen::Map<const Field>(N_VGetArrayPointer(y), g.nx, g.ny);
    if (log && i + 1 < snaps.size()) log->snapshot(t, W, cyc.pressure_on(W));
  }
  // The final surface: one more steady cycle to observe it (its wear is not applied).
  rep.worn = Eigen::Map<const Field>(N_VGetArrayPointer(y), g.nx, g.ny);
  WearCycle c = cyc.steady(N_end, rep.worn);
  if (log) log->snapshot(N_end, rep.worn, cyc.pressure());
  keep(rep, std::move(c), log, cyc.simulated());
  model.surface = model.surface0 - rep.worn;
  it.stats(rep.steps, rep.rejected);
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
    case WearIntegrator::arkode:  // the measured better of the two (docs/wear.md)
    case WearIntegrator::erk:
      return integrate_ode(model, cycles, log, false);
    case WearIntegrator::dirk:
      return integrate_ode(model, cycles, log, true);
  }
  throw InputError("wear.integrator: unknown");
}

}  // namespace fretbem
