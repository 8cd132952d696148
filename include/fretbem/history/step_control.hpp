// Sub-steps of rows whose normal load changes: there the Coulomb bound mu p moves within the
// row and the increment depends on the step. Without load.tolerance such a row is solved in
// load.substeps equal sub-steps; with it (error-controlled load steps) every solved step
// carries an embedded estimate of its error in the work, from the bound and slip of this step
// and the one before (no second solve), and a row is solved in as many equal sub-steps as the
// estimate's running rate and order ask for. Sub-steps are internal: a row of the path stays
// one output row (docs/algorithms.md, "Sub-steps of a row" and "Error-controlled load steps").
#pragma once

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

/// Sub-steps for a row of `span` periods when the estimated error per period is `rate` x h^2
/// in steps of h periods (the trapezoid's order; rate in 1/period^2): the fewest equal
/// sub-steps that bring it to `tolerance`, between 1 and kMaxSubsteps; 1 without a rate yet.
int substeps_for(double span, double rate, double tolerance);

}  // namespace fretbem
