// The two ARKODE steppers of the wear ODE (explicit ERKStep, implicit ARKStep) behind one
// face, their set-up, and ARKODE failures as one line. Internal to src/wear.
#pragma once

#include "ode_data.hpp"

namespace fretbem::wear_detail {

/// An ERKStep or ARKStep memory and its linear solver, freed with it. Times and steps in
/// cycles N.
struct ArkodeStepper {
  void* mem = nullptr;
  SUNLinearSolver ls = nullptr;
  bool implicit = false;
  ArkodeStepper() = default;
  ArkodeStepper(const ArkodeStepper&) = delete;
  ArkodeStepper& operator=(const ArkodeStepper&) = delete;
  ~ArkodeStepper();
  int stop(double t);
  int max_step(double h);
  /// One step towards tout (ARK_ONE_STEP); t receives the time reached.
  int evolve(double tout, N_Vector y, double* t);
  /// Restart at (t, y) with a first step h (resume): options are kept, the step-size
  /// controller's history is not.
  int reset(double t, N_Vector y, double h);
  double next_step();
  void stats(long& steps, long& fails);
};

/// Throws SolverError naming the ARKODE call `what`, the wear cycle N (when >= 0), the flag
/// and the keys that steer the integrator, for a negative flag.
void check(int flag, const char* what, double N = -1.0);

/// Creates `it`'s stepper (it.implicit chooses) on y with user data d and the explicit step
/// cap h_cap (cycles).
void create(ArkodeStepper& it, N_Vector y, SUNContext ctx, OdeData& d, double h_cap);

}  // namespace fretbem::wear_detail
