// Exact differential tangential stiffness k_x = dF_x/dU_x of the current stick set
// (docs/algorithms.md, "Differential stiffness"): one linear solve with a unit rigid shift on the
// stick nodes and a zero traction increment on slip and open nodes — no finite differences.
#pragma once

#include <cstdint>
#include <deque>
#include <vector>

#include "fretbem/contact/interface_state.hpp"
#include "fretbem/contact/preconditioning.hpp"
#include "fretbem/contact/tangential_operator.hpp"

namespace fretbem {

struct StiffnessResult {
  double kx = 0.0;  ///< N/m; +inf when every node of a periodic grid sticks (no mean mode)
  int iterations = 0;
  double residual = 0.0;        ///< RMS residual of C psi = e_x at the stop (1: no shift matched)
  double kx_error = 0.0;        ///< estimated relative error of kx at the stop (<= 0.1 tolerance)
  bool preconditioned = false;  ///< the Fourier-preconditioned CG was used
  bool reused = false;          ///< the stick set was one of the recently solved ones
};

class StiffnessSolver {
 public:
  /// Throws InputError when tolerance is below the operator's min_tolerance() (float FFTs).
  /// `precondition`: Fourier preconditioner z = S K_z^-1 S r of the CG (as the projected
  /// tangential CG; automatic: PreconditionDecision::for_set of the stick nodes).
  StiffnessSolver(TangentialOperator& op, double tolerance, int max_iterations,
                  Precondition precondition = Precondition::automatic);
  /// Solves C psi = e_x on the stick nodes of `state` (psi = 0 elsewhere), warm-started from
  /// the previous solution restricted to the new stick set. k_x = J h^2 with the energy value
  /// J = 2 e.psi - psi.C psi, whose error is quadratic in the solve's (sum psi_x is linear in
  /// it): the CG stops when J's estimated relative error is below 0.1 tolerance, or the
  /// residual below the tolerance, whichever comes first (about half the iterations of the
  /// residual test alone). Throws SolverError when neither is reached.
  /// `start` (component 0, on the grid; ignored when empty): the CG's start instead, imaged by
  /// one product; the result then depends on (state, start) alone: no reuse of a known set.
  StiffnessResult solve(const StateField& state, const Field* start = nullptr);
  /// The last solve's psi (component 0, Pa/m: the traction per unit shift on the stick nodes,
  /// zero elsewhere), or null when that solve ran no CG (a reused set, no stick node, a rigid
  /// periodic interface).
  const Field* solution() const { return solved_ ? &psi_[0] : nullptr; }

 private:
  class Iteration;  // the CG problem of one solve (stiffness.cpp)
  void warm_start(const std::vector<std::uint8_t>& stick);
  void given_start(const std::vector<std::uint8_t>& stick, const Field& start);

  TangentialOperator& op_;
  double tol_;
  int max_it_;
  PreconditionDecision preconditioning_;
  std::vector<Eigen::Index> nodes_;    ///< grid indices of the stick nodes of this solve
  std::vector<std::uint8_t> psi_set_;  ///< stick flags (per grid node) psi_ is supported on
  VecField psi_, u_, r_, z_, d_, q_;   ///< u_ = C psi_ on the whole grid
  /// k_x of recent stick sets: a cyclic run meets the same sets again (the full contact after
  /// every reversal, the smallest set at every turning point, and with solver.predictor =
  /// cycle whole cycles of them). Sets are kept one bit per node.
  struct Known {
    std::size_t count;                 ///< stick nodes (a cheap first comparison)
    std::vector<std::uint64_t> stick;  ///< bit k: node k sticks
    double kx;
  };
  std::deque<Known> known_;
  std::int64_t solves_ = 0;
  bool solved_ = false;  ///< the last solve() ran the CG: psi_ is its solution
};

}  // namespace fretbem
