// CyclePredictor: the converged tangential tractions of recent steps, offered as the start of
// the same step one load cycle later (solver.predictor = cycle, issue 13).
#pragma once

#include <cstdint>
#include <deque>
#include <memory>
#include <vector>

#include "fretbem/history/load_path.hpp"

namespace fretbem {

class CyclePredictor {
 public:
  /// Memory bound: at most this many bytes per grid cell for all remembered tractions (one
  /// component on the contact nodes of a Hertz cycle of 64 steps at 20 % contact: ~100; the
  /// node list is shared while the contact does not change).
  static constexpr double kBytesPerCell = 128.0;

  /// The traction (Pa, full grid, operator components) remembered for a step that went from
  /// load `prev` to load `cur`, or nullptr. The pointer is valid until the next call.
  const VecField* find(const LoadStep& prev, const LoadStep& cur, Eigen::Index nx, Eigen::Index ny);
  /// Remembers the traction on the contact nodes (bound > 0) after the step prev -> cur.
  void remember(const LoadStep& prev, const LoadStep& cur, const VecField& traction,
                const Field& bound);

 private:
  struct Entry {
    LoadStep prev, cur;
    std::shared_ptr<const std::vector<Eigen::Index>> nodes;
    std::vector<std::vector<double>> values;  ///< per component, per node
  };
  std::deque<Entry> entries_;
  std::size_t stored_ = 0;  ///< doubles and indices held (a shared node list once)
  VecField guess_;
};

}  // namespace fretbem
