// When the conjugate-gradient solves (normal, tangential, stiffness) use the Fourier
// preconditioner z = S K^-1 S r: the one decision all three take, from solver.precondition
// and, when that is automatic, from the measured break-evens below.
#pragma once

#include <cstdint>
#include <vector>

#include "fretbem/core/solver_options.hpp"
#include "fretbem/elastic/grid.hpp"

namespace fretbem {

/// Nodes of the largest 4-connected patch of contact nodes (bound > 0).
std::int64_t largest_contact_patch(const Field& bound);

class PreconditionDecision {
 public:
  /// Automatic normal preconditioning from this many grid cells (256 x 256): bench_normal_cost
  /// measured the preconditioned CG 0.6-0.8x the plain CG's time there (and ~1.05x at 128 x 128).
  static constexpr std::int64_t kGridCells = 256 * 256;
  /// Automatic tangential and stiffness preconditioning from this largest patch of the solved
  /// node set (a disc of radius ~25 cells). Plain CG on a patch needs iterations growing with
  /// its diameter (the square root of the condition number); the preconditioner removes that
  /// growth at the price of a second transform pair per iteration. Measured (bench_tangential,
  /// CPU time PCG / plain): Hertz contact (one patch of 3252, 12900, 51540 nodes at n = 128,
  /// 256, 512) 0.7, 0.5-0.6, 0.4; rough contact with largest patches of 174-614 nodes
  /// 0.97-1.25, of 2407 nodes 0.74-0.83 (docs/performance.md).
  static constexpr std::int64_t kPatchNodes = 2048;

  explicit PreconditionDecision(Precondition mode) : mode_(mode) {}
  Precondition mode() const { return mode_; }

  /// The normal solve on `grid`: automatic = on from kGridCells cells.
  bool for_grid(const Grid& grid) const;
  /// A solve on the nodes where `set` is positive: automatic = on when their largest patch
  /// has kPatchNodes nodes or more.
  bool for_set(const Field& set) const;
  /// for_set for the set whose positive nodes are `nodes` (grid indices, ascending), with
  /// `set` built only when needed: fewer nodes than kPatchNodes cannot form such a patch, and
  /// the flood fill (a pass over the grid: 4 % of a full-sliding step of rough_monotone.ini,
  /// perf) is remembered for the last node list.
  template <class MakeSet>
  bool for_nodes(const std::vector<Eigen::Index>& nodes, MakeSet&& make_set) {
    if (mode_ != Precondition::automatic) return mode_ == Precondition::on;
    if (std::int64_t(nodes.size()) < kPatchNodes) return false;
    if (nodes != key_) {
      key_ = nodes;
      answer_ = largest_contact_patch(make_set()) >= kPatchNodes;
    }
    return answer_;
  }

 private:
  Precondition mode_;
  std::vector<Eigen::Index> key_;  ///< node list of the last flood fill, and its answer
  bool answer_ = false;
};

}  // namespace fretbem
