// The frozen-slip linear solver of the implicit wear integrator's modified Newton iteration.
#include <arkode/arkode_arkstep.h>

#include "fretbem/core/errors.hpp"
#include "ode_data.hpp"

namespace fretbem::wear_detail {
namespace {

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

// `delta`: ARKODE's tolerance for the linear solve, a 2-norm in the units of y (m; arkLsSolve:
// 0.05 times the Newton tolerance, over the mean error weight, times sqrt of the length).
int frozen_solve(SUNLinearSolver S, SUNMatrix, N_Vector x, N_Vector b, realtype delta) {
  auto& c = *static_cast<FrozenSlipContent*>(S->content);
  realtype gamma = 0.0;
  ARKStepGetCurrentGamma(c.arkode, &gamma);
  if (newton_matrix_solve(*c.data, b, x, gamma, delta) != 0) return SUNLS_PSOLVE_FAIL_UNREC;
  // The Newton iterate z + x is evaluated next (or, converged, is the stage value the next
  // stage's predictor or the next step's first stage starts from): its pressure is about the
  // linearisation's p + q, exact on an unchanged contact set.
  const WearPreconditioner& pre = *c.data->pre;
  if (pre.ready()) c.data->cyc.predict(slab(*c.data, x), pre.pressure_change());
  return 0;
}

int frozen_free(SUNLinearSolver S) {
  delete static_cast<FrozenSlipContent*>(S->content);
  S->content = nullptr;
  SUNLinSolFreeEmpty(S);
  return 0;
}

}  // namespace

SUNLinearSolver frozen_slip_solver(OdeData& d, void* arkode, SUNContext ctx) {
  SUNLinearSolver S = SUNLinSolNewEmpty(ctx);
  if (!S) throw SolverError("SUNDIALS: no linear solver");
  S->content = new FrozenSlipContent{&d, arkode};
  S->ops->gettype = frozen_type;
  S->ops->solve = frozen_solve;
  S->ops->free = frozen_free;
  return S;
}

}  // namespace fretbem::wear_detail
