// Stepper::solve_increment and bound_after_slip: one tangential increment, solved again while
// the friction law lowers the bound of nodes that slipped in it (static/kinetic: mu_k from the
// moment a node slips).
#include <cmath>

#include "fretbem/history/stepper.hpp"

namespace fretbem {

// The increment by the model's solver (with its fallbacks); a failure names the step and hands
// its inputs to failed_solve.h5. The iterations are summed over the re-solves.
TangentialResult Stepper::solve_increment(const TangentialIncrement& inc, const VecField& tau0,
                                          const VecField& u0, StepRecord& rec) {
  TangentialResult r;
  int iterations = 0;
  do {
    try {
      r = model_.tangential->solve(inc, state_.traction, state_.displacement);
      iterations += r.iterations;
    } catch (const SolverError& e) {
      FailedSolve f;
      f.solve = "tangential";
      f.control = inc.control == TangentialControl::force ? "force" : "displacement";
      f.target = inc.target, f.bound = bound_, f.tau0 = tau0, f.u0 = u0;
      f.direction = model_.tangential_operator->direction();
      fail(rec, e, std::move(f));
    }
  } while (bound_after_slip(u0, r.shift));
  r.iterations = iterations;
  return r;
}

// The nodes that slipped in the increment just solved, by the rule of
// InterfaceState::classify (on the bound, |s| above the slip threshold), handed to the law;
// true when it lowered the bound (the caller solves the increment again, warm-started from
// this solution). The slip is s = dU - (u - u0) in the operator's components.
bool Stepper::bound_after_slip(const VecField& u0, const Eigen::VectorXd& shift) {
  if (!model_.friction->evolves()) return false;
  const double eps = model_.scenario.solver.tolerance, threshold = slip_threshold();
  const int nc = int(state_.traction.size());
  Field slipped = Field::Zero(bound_.rows(), bound_.cols());
  for (Eigen::Index k = 0; k < bound_.size(); ++k) {
    if (!(bound_(k) > 0.0)) continue;
    double t2 = 0.0, s2 = 0.0;
    for (int c = 0; c < nc; ++c) {
      const double sc = shift(c) - (state_.displacement[c](k) - u0[c](k));
      t2 += state_.traction[c](k) * state_.traction[c](k), s2 += sc * sc;
    }
    if (std::sqrt(t2) >= bound_(k) * (1.0 - eps) && std::sqrt(s2) > threshold) slipped(k) = 1.0;
  }
  return model_.friction->after_slip(state_, slipped, bound_);
}

}  // namespace fretbem
