// Exact differential tangential stiffness k_x = dF_x/dU_x of the current stick set
// (DESIGN §1 "Observables"): one linear solve with a unit rigid shift on the stick nodes and a
// zero traction increment on slip and open nodes — no finite differences.
#pragma once

#include "fretbem/contact/interface_state.hpp"
#include "fretbem/contact/tangential_operator.hpp"

namespace fretbem {

struct StiffnessResult {
  double kx = 0.0;  ///< N/m
  int iterations = 0;
  double residual = 0.0;
};

class StiffnessSolver {
 public:
  /// Throws InputError when tolerance is below the operator's min_tolerance() (float FFTs).
  StiffnessSolver(TangentialOperator& op, double tolerance, int max_iterations);
  /// Solves C psi = e_x on the stick nodes of `state` (psi = 0 elsewhere), warm-started from
  /// the previous solution; k_x = sum psi_x h^2. Throws SolverError when not converged.
  StiffnessResult solve(const StateField& state);

 private:
  TangentialOperator& op_;
  double tol_;
  int max_it_;
  VecField psi_, u_, r_, d_, q_;
  Field last_stick_;  ///< stick set of the last solve, and its k_x
  double last_kx_ = 0.0;
};

}  // namespace fretbem
