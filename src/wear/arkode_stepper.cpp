// ARKODE steppers of the wear ODE: how each is set up (method, tolerances, Newton) and driven.
#include "arkode_stepper.hpp"

#include <arkode/arkode_arkstep.h>
#include <arkode/arkode_erkstep.h>
#include <sunlinsol/sunlinsol_spgmr.h>

#include <algorithm>
#include <cstdlib>
#include <string>

#include "fretbem/core/errors.hpp"
#include "fretbem/core/format.hpp"

namespace fretbem::wear_detail {

ArkodeStepper::~ArkodeStepper() {
  if (implicit)
    ARKStepFree(&mem);
  else
    ERKStepFree(&mem);
  if (ls) SUNLinSolFree(ls);
}

int ArkodeStepper::stop(double t) {
  return implicit ? ARKStepSetStopTime(mem, t) : ERKStepSetStopTime(mem, t);
}

int ArkodeStepper::max_step(double h) {
  return implicit ? ARKStepSetMaxStep(mem, h) : ERKStepSetMaxStep(mem, h);
}

int ArkodeStepper::evolve(double tout, N_Vector y, double* t) {
  return implicit ? ARKStepEvolve(mem, tout, y, t, ARK_ONE_STEP)
                  : ERKStepEvolve(mem, tout, y, t, ARK_ONE_STEP);
}

int ArkodeStepper::reset(double t, N_Vector y, double h) {
  const int f = implicit ? ARKStepReset(mem, t, y) : ERKStepReset(mem, t, y);
  if (f < 0) return f;
  return implicit ? ARKStepSetInitStep(mem, h) : ERKStepSetInitStep(mem, h);
}

double ArkodeStepper::next_step() {
  double h = 0.0;
  implicit ? ARKStepGetCurrentStep(mem, &h) : ERKStepGetCurrentStep(mem, &h);
  return h;
}

void ArkodeStepper::stats(long& steps, long& fails) {
  if (implicit)
    ARKStepGetNumSteps(mem, &steps), ARKStepGetNumErrTestFails(mem, &fails);
  else
    ERKStepGetNumSteps(mem, &steps), ERKStepGetNumErrTestFails(mem, &fails);
}

// A failed ARKODE call as one line a user can act on ("ARKODE step failed
// (flag -22)" named nothing): the call, the wear cycle N when known, SUNDIALS' name of the
// flag, and the keys that steer the integrator.
void check(int flag, const char* what, double N) {
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

namespace {

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
void create_implicit(ArkodeStepper& it, N_Vector y, SUNContext ctx, OdeData& d, double h0) {
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
    // cycle at it (770 -> 516 simulated cycles to 1e6 at n = 64, docs/wear.md), and the
    // trivial predictor: each implicit stage's first iterate is the step's start, whose wear
    // map the explicit first stage has just evaluated (wear_rhs answers it without a cycle).
    // rough_fretting_wear.ini at wear.rtol = 1e-2, against the predictor of maximum order:
    // n = 128 to N = 1e5 50 evaluations and 3817 convolutions against 115 and 6635; n = 256
    // to N = 1e4 34 and 3080 against 69 and 4492 (docs/wear.md, "Cost").
    check(ARKStepSetDeduceImplicitRhs(it.mem, SUNTRUE), "deduced stage derivative");
    check(ARKStepSetPredictorMethod(it.mem, 0), "predictor");
    return;
  }
  it.ls = SUNLinSol_SPGMR(y, SUN_PREC_RIGHT, 5, ctx);
  check(ARKStepSetLinearSolver(it.mem, it.ls, nullptr), "linear solver");
  check(ARKStepSetPreconditioner(it.mem, wear_psetup, wear_psolve), "preconditioner");
  check(ARKStepSetJacTimes(it.mem, nullptr, wear_jtimes), "Jacobian-vector product");
}

}  // namespace

void create(ArkodeStepper& it, N_Vector y, SUNContext ctx, OdeData& d, double h_cap) {
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

}  // namespace fretbem::wear_detail
