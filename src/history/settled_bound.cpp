// Stepper::settle_bound: the bound at a step's end for friction laws whose mu follows the
// node's history within the step (evolving): the increment is solved again with mu_1 p_1, mu_1
// from the history at the step's end by the work's trapezoid, until the bound it ends on is the
// one it was solved with (docs/algorithms.md, "Evolving friction").
#include <algorithm>
#include <cmath>
#include <sstream>

#include "fretbem/history/stepper.hpp"

namespace fretbem {

namespace {

// Re-solves of one increment at most. Each is a fixed-point step g <- mu(X_1(s(g))) p_1 that
// contracts the bound's change by the law's slope times the step's work relative to the bound
// (measured on the Hertz cycle of docs/algorithms.md, "Evolving friction": 0.15-0.5 per
// re-solve).
constexpr int kMaxSettles = 50;
// A re-solve that shrinks the change by less than this does not contract: nodes at the slip
// front flip between slipping (X grows, g rises) and stuck (g stays), and the bound alternates
// between the two. The step towards g_1 is then halved each time, which settles the bound
// between them (a flipping node sits where its slip is at the threshold).
constexpr double kFloorRatio = 0.9;

}  // namespace

// Slip increment s = dU - (u - u0) per node and its length (work_.slip); with `nodes` on those
// only (a contact that does not change: s elsewhere is left unset, work_'s slip, pressure and
// work zero there).
void Stepper::step_slip_vectors(const VecField& u0, const Eigen::VectorXd& dU, VecField& s,
                                const std::vector<Eigen::Index>* nodes) {
  const int nc = int(state_.traction.size());
  // Sized, not filled: every entry read is written below (a filled copy per component was a
  // copy of the grid per step).
  s.resize(std::size_t(nc));
  for (Field& f : s) f.resize(bound_.rows(), bound_.cols());
  auto slip_at = [&](Eigen::Index k) {
    double len2 = 0.0;
    for (int c = 0; c < nc; ++c) {
      const double sc = dU(c) - (state_.displacement[c](k) - u0[c](k));
      s[c](k) = sc, len2 += sc * sc;
    }
    work_.slip(k) = len2;
  };
  if (nodes) {
    if (!work_zero_off_contact_) {
      const Field zero = Field::Zero(bound_.rows(), bound_.cols());
      work_.slip = zero, work_.pressure = zero, work_.work = zero;
    }
    work_zero_off_contact_ = true;
    for (const Eigen::Index k : *nodes) slip_at(k);
    for (const Eigen::Index k : *nodes) work_.slip(k) = std::sqrt(work_.slip(k));
    return;
  }
  work_zero_off_contact_ = false;
  work_.slip.resize(bound_.rows(), bound_.cols());
  for (Eigen::Index k = 0; k < bound_.size(); ++k) slip_at(k);
  // The roots in one vectorised pass: a root per cell inside the loop above stalled it (a third
  // of the function's time in a steady n = 256 cycle, perf annotate).
  work_.slip = work_.slip.sqrt();
}

// The step's slip split by the bound's quadrature (step_work.hpp), with the node states the
// step would end with; state_.state keeps the previous step's states (accumulate_slip reads
// them as the step's start).
StepSlip Stepper::step_slip(const VecField& u0, const VecField& tau0, const Eigen::VectorXd& dU) {
  VecField s;
  step_slip_vectors(u0, dU, s);
  const StateField before = state_.state;
  state_.classify(bound_, model_.scenario.solver.tolerance, work_.slip, slip_threshold());
  const StepStart start = step_start(before, tau0);
  StepSlip out{Field::Zero(bound_.rows(), bound_.cols()), Field::Zero(bound_.rows(), bound_.cols()),
               Field::Zero(bound_.rows(), bound_.cols())};
  const auto slip = std::uint8_t(NodeState::slip);
  for (Eigen::Index k = 0; k < bound_.size(); ++k) {
    const double len = work_.slip(k);
    const BoundWeights w = bound_weights(&start, state_, bound_, s, len, k);
    if (state_.state(k) == slip) out.path(k) = len;
    out.start_work(k) = w.start * bound_start_(k) * len;
    out.end_pressure_slip(k) = w.end * state_.pressure(k) * len;
  }
  state_.state = before;
  return out;
}

// Solves the increment again while the law moves the bound it ends on (by more than the solver
// tolerance relative to max g; under Coupling::coupled by more than the coupling tolerance, to
// which the alternation that calls this converges p and tau; by more than `floor` if larger);
// returns the iterations of the re-solves. A bound still moving by more than sqrt(tolerance) (1e-4
// at the default: far above the solve's own floor) after kMaxSettles re-solves is an error naming
// the step.
int Stepper::settle_bound(const TangentialIncrement& inc, const VecField& tau0, TangentialResult& r,
                          StepRecord& rec, double floor) {
  const FrictionLaw& law = *model_.friction;
  if (!law.settles_within_step() || bound_start_.size() != bound_.size()) return 0;
  const SolverSpec& sv = model_.scenario.solver;
  const double tol = std::max(floor, model_.half_space->cross_coupled()
                                         ? std::max(sv.tolerance, sv.coupling_tolerance)
                                         : sv.tolerance);
  int iterations = 0;
  Field g1;
  double previous = 0.0, omega = 1.0;
  for (int m = 0;; ++m) {
    law.end_bound(state_, step_slip(*inc.u0, tau0, r.shift), g1);
    const double scale = g1.maxCoeff();
    const double change = scale > 0.0 ? (g1 - bound_).abs().maxCoeff() / scale : 0.0;
    if (change <= tol) break;
    if (m > 0 && change > kFloorRatio * previous) omega *= 0.5;
    if (omega * change <= tol) break;
    if (m == kMaxSettles) {
      if (change <= std::sqrt(tol)) break;
      FailedSolve f;
      f.solve = "tangential";
      f.control = inc.control == TangentialControl::force ? "force" : "displacement";
      f.target = inc.target, f.bound = bound_, f.tau0 = tau0, f.u0 = *inc.u0;
      f.direction = model_.tangential_operator->direction();
      std::ostringstream msg;
      msg << "the evolving friction bound at the step's end did not settle: it still moved by "
          << change << " of its largest value after " << m
          << " re-solves; mu moves too far within the step, use more steps";
      fail(rec, SolverError(msg.str()), std::move(f));
    }
    previous = change;
    bound_ += omega * (g1 - bound_);
    r = solve_increment(inc, tau0, *inc.u0, rec);
    iterations += r.iterations;
  }
  return iterations;
}

}  // namespace fretbem
