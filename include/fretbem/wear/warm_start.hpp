// WearWarmStart: where a wear-map evaluation (WearCycles::steady) starts its normal-type
// solves, and the recent evaluations whose pressures it extrapolates to a new worn depth.
// Pressures in Pa, worn depths in m; every Field is this rank's slab of the grid, and every
// sum over the grid goes through its Communicator.
#pragma once

#include <functional>
#include <vector>

#include "fretbem/elastic/grid.hpp"
#include "fretbem/parallel/communicator.hpp"

namespace fretbem {

struct WearWarmStart {
  /// The last evaluation's pressure and the corrective pressure p* of its virgin loading
  /// (Ciavarella–Jäger; empty where the loop is not Masing's). Empty: cold.
  Field pressure, corrective;
  /// The latest evaluations' worn depths and their pressures, in evaluation order (oldest
  /// first), at most kDepth of each: the integrator's path through the worn depths.
  std::vector<Field> worn_path, pressure_path;
  /// A state the integrator is about to evaluate, predicted from the last evaluation (its worn
  /// depth plus a frozen-slip Newton correction x, its pressure plus the correction's linear
  /// response q, WearPreconditioner): one more point of the fit until the next evaluation.
  /// Empty: none.
  Field predicted_worn, predicted_pressure;
  /// Three evaluations span the affine combinations the integrator forms of its recent
  /// states (a TR-BDF2 stage predictor interpolates the last step's three stage values).
  static constexpr int kDepth = 3;
  /// Bytes per grid cell the path and the predicted state hold (MemoryCosts::kWear counts
  /// them).
  static constexpr double kBytesPerCell = 2.0 * (kDepth + 1) * sizeof(double);

  /// Appends an evaluation (worn depth, pressure of its normal solve), dropping the oldest
  /// beyond kDepth; `pressure` becomes the last one.
  void remember(const Field& worn, const Field& pressure);
  /// Predicts the next evaluation: the last one's worn depth moved by `worn_change` (m), its
  /// pressure by `pressure_change` (Pa). Ignored before the first evaluation.
  void predict(const Field& worn_change, const Field& pressure_change);
  /// The start of the normal solve on worn depth `worn`: the path's pressures extrapolated
  /// affinely to it (warm_start.cpp gives the rule), the last pressure where the path has one
  /// evaluation, empty (cold) where it has none.
  Field start_for(const Field& worn, const Communicator& comm) const;
  /// Every non-empty field mapped by f (slab <-> whole grid for checkpoints).
  WearWarmStart mapped(const std::function<Field(const Field&)>& f) const;
};

}  // namespace fretbem
