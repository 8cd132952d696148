// Pre-flight checks: every refusal a run makes before its first solve that ties several keys,
// the load path and the surface together. `fretbem check` and `fretbem run` both go through
// prepare_model (model.hpp), which calls these, so check refuses exactly what run refuses
// (issue 14, item 8).
#pragma once

#include "fretbem/history/load_path.hpp"
#include "fretbem/scenario/scenario.hpp"
#include "fretbem/surface/surface.hpp"

namespace fretbem {

/// Scales of a scenario, SI: what the dimensionless bounds and `fretbem check` report.
struct ContactScales {
  double E_star = 0.0, G_star = 0.0;  ///< Pa
  /// Hertz contact radius a (m), peak pressure p0 (Pa) and approach delta (m) of a sphere at
  /// the largest normal force of the path; 0 for other surfaces or indentation control.
  double hertz_a = 0.0, hertz_p0 = 0.0, hertz_delta = 0.0;
  /// A displacement the contact makes at its largest normal load (m): the Hertz approach, the
  /// largest indentation, or F / (E* L) (a load F spread over the L x L domain), whichever
  /// applies and is largest; at least the surface's height range.
  double normal_displacement = 0.0;
  /// Full-sliding shift U* = mu delta E* / G* (m) where delta is known before a solve (Hertz
  /// approach or the indentation); 0 otherwise.
  double full_sliding_shift = 0.0;
  double max_normal_force = 0.0;      ///< N, 0 when every step is indentation-controlled
  double max_indentation = 0.0;       ///< m
  double max_tangential_shift = 0.0;  ///< m, displacement-controlled steps
};

ContactScales contact_scales(const Scenario& sc, const LoadPath& path, const Field& surface);

/// Throws InputError naming the key or file when the scenario, its path and surface cannot be
/// run: indentation on a periodic grid, wear without a cyclic path, a table force at or past
/// mu Fz, and the dimensionless bounds of the arithmetic (preflight.cpp).
void check_before_solve(const Scenario& sc, const LoadPath& path, const Field& surface);

}  // namespace fretbem
