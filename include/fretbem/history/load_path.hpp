// LoadPath: the scripted load history as a list of steps (README "Path semantics").
#pragma once

#include <filesystem>
#include <optional>
#include <vector>

#include "fretbem/contact/tangential_operator.hpp"
#include "fretbem/scenario/scenario.hpp"

namespace fretbem {

/// The normal load of a step: force (N) or indentation (m).
struct NormalLoad {
  bool force_control = true;
  double value = 0.0;
  bool operator==(const NormalLoad&) const = default;
};

/// load.interpolation = cubic: the path's rates of change at a table row (per unit of time),
/// the slopes of its spline (history/load_spline.hpp).
struct PathRate {
  double normal = 0.0;    ///< of the normal load's value (N or m)
  Vec2 target{0.0, 0.0};  ///< of the tangential target (N or m)
};

/// One load step. Row 0 of a path is the initial normal loading with zero tangential load.
struct LoadStep {
  double time = 0.0;
  int cycle = 0;
  NormalLoad normal;
  Control control = Control::force;
  /// Tangential target, global x-y: force in units of mu F_z (force control, so that it follows
  /// a normal force known only after the normal solve) or displacement (m).
  Vec2 target{0.0, 0.0};
  bool relative = true;  ///< force target in units of mu F_z (ramp, sine) or in N (tables)
  bool turning = false;  ///< a turning point of the path (fields are saved there)
  /// A row of a table interpolated by a spline: its slopes there, shared by the rows on either
  /// side (the path is C1 through it). Absent: the load is linear up to this step.
  std::optional<PathRate> rate{};
};

/// The cycle of path time t (period 1): its integer part, floor(t), within a rounding error
/// of 1e-12 (a sine step at t = 2 - 1e-16 is in cycle 2); clamped to the range of an int.
int cycle_of_time(double t);
/// The cycle that contains the interval (t_prev, t]: ceil(t) - 1, same rounding and clamp.
/// A step's increment belongs to it (cycles.csv).
int cycle_containing_end(double t);

struct LoadPath {
  std::vector<LoadStep> steps;
  /// The single direction of every tangential target, when the history is collinear.
  std::optional<Vec2> collinear_direction() const;
  /// True when the tangential target is monotone from step a to step b (same direction of
  /// motion, no reversal) and the normal load is constant: a Ciavarella–Jäger segment.
  bool monotone(std::size_t a, std::size_t b) const;
};

/// Builds the path of a scenario; table paths read their CSV (InputError on any problem).
LoadPath make_load_path(const Scenario& sc);
/// Reads a path table: columns `time` plus any of Fz, delta, Fx, Fy, Ux, Uy.
LoadPath read_load_table(const std::filesystem::path& file, const LoadSpec& spec, double mu);

}  // namespace fretbem
