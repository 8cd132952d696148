// Pre-flight checks: every refusal a run makes before its first solve that ties several keys,
// the load path and the surface together. `fretbem check` and `fretbem run` both go through
// prepare_model (model.hpp), which calls these, so check refuses exactly what run refuses.
#pragma once

#include "fretbem/elastic/closed_forms.hpp"
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
  /// Full-sliding shift U* = mu delta E* / G* (m; full_sliding_shift below) with delta the
  /// approach where it is known before a solve (Hertz approach or the largest indentation),
  /// else normal_displacement, an upper bound of it (approach_known false).
  double full_sliding_shift = 0.0;
  bool approach_known = false;
  /// Radius of the contact the small-slip guard compares shifts with (m): Hertz a of a sphere
  /// at the largest normal load (sqrt(R delta) under indentation); for other surfaces, whose
  /// square domain is the nominal contact, half the domain's shorter side.
  double contact_radius = 0.0;
  double max_normal_force = 0.0;      ///< N, 0 when every step is indentation-controlled
  double max_indentation = 0.0;       ///< m
  double max_tangential_shift = 0.0;  ///< m, displacement-controlled steps
};

/// Shifts past this many contact radii are refused unless load.allow_large_shift = true: the
/// model keeps the contact geometry fixed (small slip: the indenter's heights stay over the
/// same half-space points), and a shift of a whole contact radius moves the contact so far
/// that its start and end footprints overlap on only 39 % of their area (two circles of
/// radius a whose centres lie a apart) - sliding, not fretting. Past kWarnShiftOverContactRadius
/// (overlap 84 %) a warning says so.
inline constexpr double kMaxShiftOverContactRadius = 1.0, kWarnShiftOverContactRadius = 0.25;

/// U* = mu delta E*/G* (m): the rigid shift at which a contact of approach delta slides as a
/// whole (Mindlin; the paper's normalisation), from the closed-form module.
using closed_forms::full_sliding_shift;

ContactScales contact_scales(const Scenario& sc, const LoadPath& path, const Field& surface);

/// Throws InputError naming the file (or "surface") when a height reaches past 1e100 m, the
/// bound of every dimensional input; make_surface calls it for every surface it makes.
void check_heights(const Scenario& sc, const Field& surface);

/// Throws InputError naming the key or file when the scenario, its path and surface cannot be
/// run: indentation on a periodic grid, wear without a cyclic path, a table force at or past
/// mu Fz, a shift past the small-slip bound, and the dimensionless bounds of the arithmetic
/// (preflight.cpp). Shifts past kWarnShiftOverContactRadius go to input_warning.
void check_before_solve(const Scenario& sc, const LoadPath& path, const Field& surface);

}  // namespace fretbem
