// Sub-steps of rows whose normal load changes: there the Coulomb bound mu p moves within the
// row and the increment depends on the step. Without load.tolerance such a row is solved in
// load.substeps equal sub-steps; with it (error-controlled load steps) every solved step
// carries an embedded estimate of its error in the work, from the bound and slip of this step
// and the one before (no second solve), and a row is solved in as many equal sub-steps as the
// estimate's rate (PeriodRate) and order ask for. Sub-steps are internal: a row of the path stays
// one output row (docs/algorithms.md, "Sub-steps of a row" and "Error-controlled load steps").
#pragma once

#include <vector>

#include "fretbem/contact/tangential_operator.hpp"
#include "fretbem/history/load_path.hpp"
#include "fretbem/history/model.hpp"

namespace fretbem {

/// Sub-steps of a row at most.
constexpr int kMaxSubsteps = 256;

/// The equal sub-steps of every row whose normal load changes when the step control is off:
/// load.substeps (resolved to 1 in wear runs, whose integrators replay rows whole, and by
/// default under coupled: resolve_load_substeps), 1 with load.tolerance > 0 (the controller
/// chooses).
int fixed_substeps(const Model& model);

/// The solves of path row k without load.tolerance: fixed_substeps where its normal load
/// changes (bound_moves_within), else 1 (the initial loading, k = 0, included).
int row_substeps(const Model& model, std::size_t k);

/// Whether the sub-steps of rows are remembered by the cycle predictor and start from the
/// same sub-step one period earlier (Model::cycle_predictor, one traction component; measured
/// in step_control.cpp). Rows solved whole take the predictor whatever this says.
bool substeps_predicted(const Model& model);

/// The cycle predictor's memory bound (bytes per grid cell) for a run of `sc` on `path`:
/// CyclePredictor::kBytesPerCell, times the sub-steps of a row up to
/// CyclePredictor::kSubstepsKept where rows whose normal load changes are solved in sub-steps
/// (load.substeps > 1, or load.tolerance). The memory estimate counts it (estimate_memory).
double predictor_bytes_per_cell(const Scenario& sc, const LoadPath& path);

/// Whether the bound can move within the step from a to b, so that the step's solution depends
/// on its length: the normal load changes (same control of the normal load and of the
/// tangential path at both ends). A constant normal load with a constant friction law gives
/// the same increment whatever the step, and is never subdivided.
bool bound_moves_within(const LoadStep& a, const LoadStep& b);

/// The load at fraction theta in [0, 1] of the step from a to b, the one interpolation of a
/// path within a row: time linear in theta; normal load and tangential target on the table's
/// spline where both ends carry its slopes (load.interpolation = cubic, cubic Hermite form),
/// else linear (and no slopes). Control and units are b's; the interpolated load is no turning
/// point.
LoadStep interpolate_load(const LoadStep& a, const LoadStep& b, double theta);

/// One node's bound change (Pa) and booked slip length (m) over a step of `span` periods.
struct NodeStep {
  double bound_change = 0.0;
  double slip = 0.0;
};

/// The error (J/m^2, exact minus booked) of the work of one node over step 1 booked as the
/// trapezoid (g0 + g1)/2 |s1|, from step 0 (the step before, span h0) and step 1 (span h1):
/// with g quadratic and the slip rate linear in time across both steps, the exact work
/// minus the trapezoid is (h1^3/12)(g' s'' - g'' s') at step 1's midpoint, which in the steps'
/// differences is h1^2 (dg0 |s1| - dg1 |s0|) / (6 h0 (h0 + h1)) (docs/algorithms.md).
double trapezoid_work_error(const NodeStep& step0, double h0, const NodeStep& step1, double h1);

/// The error-controlled runs' rate (1/period^2: a period's estimate is rate x h^2 in sub-steps
/// of h periods). Until a whole period has been solved (a lead-in of less than a period, then
/// the first period) it is the larger of the lead-in's mean rate and the mean over the period's
/// rows so far, never lowered within the period, and a row that raises it is solved again
/// (Stepper::solve_controlled); the first rows have no rate to go by, and a rate grown from 0
/// left the first period short of its sub-steps (docs/algorithms.md, "Run time against
/// error"). From the first whole period on, it is that period's mean, then a running mean over
/// about a period of rows (weight span / period a row): a rate held for each whole period gave
/// the same sub-steps on the bench's sphere and 1.7 % fewer convolutions on its rough surface at
/// 1e-4, and both met every tolerance measured. The count is ⌈span √(rate / tolerance)⌉ a row:
/// rounded with the rounding errors carried from row to row (the rows' mean count the wanted
/// one), the unit sphere of tests/test_step_control.cpp missed 1e-3 by -2.35e-3 in its second
/// period and 1e-4 by +1.30e-4.
class PeriodRate {
 public:
  /// The rate for the row from time t0 (periods) that ends in cycle `cycle`; < 0: none yet.
  double for_row(int cycle, double t0);
  /// The rate the row just solved (estimate `error`, span and sub-step as in add) would give
  /// the rows after it, before it is booked.
  double with_row(double error, double span, double substep) const;
  /// Whether a whole period has been solved (from then on no row is solved again).
  bool settled() const { return settled_; }
  /// Books a solved row: its estimate relative to the dissipation per period, its span and
  /// its sub-step (periods). Rows whose first step had no step before (estimate 0 there) are
  /// left out by the caller.
  void add(double error, double span, double substep, double t1);
  /// The state as numbers (the checkpoint's `step_period`) and back; a wrong count throws.
  std::vector<double> flatten() const;
  static PeriodRate unflatten(const std::vector<double>& v);
  static constexpr std::size_t kValues = 8;

 private:
  double rate_ = -1.0;                 ///< the rate in force (< 0: none)
  bool settled_ = false;               ///< rate_ is a whole period's
  double cycle_ = -1e300;              ///< the cycle being booked
  double start_ = 0.0, end_ = 0.0;     ///< the time its rows span (periods)
  double error_ = 0.0, weight_ = 0.0;  ///< its rows' estimates and span x sub-step^2
  double floor_ = 0.0;  ///< before a settled rate: the largest rate given in the cycle
};

/// Sub-steps for a row of `span` periods when the estimated error per period is `rate` x h^2
/// in steps of h periods (the trapezoid's order; rate in 1/period^2): the fewest equal
/// sub-steps that bring it to `tolerance`, between 1 and kMaxSubsteps; 1 without a rate yet.
int substeps_for(double span, double rate, double tolerance);

}  // namespace fretbem
