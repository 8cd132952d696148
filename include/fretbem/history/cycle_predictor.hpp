// CyclePredictor: the converged tangential tractions of recent steps, offered as the start of
// the same step one load cycle later (solver.predictor).
#pragma once

#include <cstdint>
#include <deque>
#include <memory>
#include <vector>

#include "fretbem/history/load_path.hpp"
#include "fretbem/parallel/communicator.hpp"

namespace fretbem {

class CyclePredictor {
 public:
  /// Memory bound: at most this many bytes per grid cell for all remembered tractions (one
  /// component on the contact nodes of a Hertz cycle of 64 steps at 20 % contact: ~100; the
  /// node list is shared while the contact does not change). The memory guard adds it to the
  /// run's estimate (estimate_memory, cost_estimate.hpp).
  static constexpr double kBytesPerCell = 128.0;
  /// A run whose rows are solved in K sub-steps remembers each sub-step: its bound is
  /// kBytesPerCell x min(K, kSubstepsKept) (x kSubstepsKept under load.tolerance), and K = 4
  /// sub-steps of 32 rows a period take 151-335 bytes per cell on the benches of
  /// tools/bench/step_control_cost.py (sphere, rough surfaces, displacement control; 19 %
  /// contact on the sphere). At n = 512 the bound is 128 MiB.
  static constexpr int kSubstepsKept = 4;

  /// For each step k of the path: whether the transition steps[k-1] -> steps[k] occurs again
  /// at a later step (only those are worth remembering). Transitions are compared on loads
  /// rounded to 1e-7 of the path's largest load: a near miss only stores one entry more or
  /// less, never changes a result. Step 0 (no transition) is false.
  static std::vector<char> repeated_later(const std::vector<LoadStep>& steps);
  /// Same, for whether the transition occurred at an earlier step (the predictor has it).
  static std::vector<char> repeated_earlier(const std::vector<LoadStep>& steps);
  /// For each step k: the latest earlier step with the same transition (the step whose
  /// traction the predictor offers at k), or -1.
  static std::vector<long> sources(const std::vector<LoadStep>& steps);

  /// The traction (Pa, full grid, operator components) remembered for a step that went from
  /// load `prev` to load `cur`, or nullptr. The pointer is valid until the next call.
  const VecField* find(const LoadStep& prev, const LoadStep& cur, Eigen::Index nx, Eigen::Index ny);
  /// The remembered traction (Pa) as the start of a step whose bound g (Pa) moved since it
  /// was remembered (a varying normal load): every node inside its disc by less than
  /// kOnBoundBand x `largest` (the largest bound over the grid, Pa) is put on it. The bound of
  /// the same row one period earlier differs by the normal solves' error, and a node remembered
  /// slipping on it lies just inside the new disc, where the solver takes it for a stick node
  /// with a whole step's slip (docs/algorithms.md, "Tangential increment").
  static void onto_moved_bound(const Field& bound, double largest, VecField& traction);
  /// Measured on the varying-load sphere of tools/bench/step_control_cost.py (solver.tolerance
  /// 1e-8): such nodes lie 1e-9 to 1e-6 of the largest bound inside; a stick node put on its
  /// bound changes only where the iteration starts.
  static constexpr double kOnBoundBand = 1e-4;

  /// Remembers the traction on the contact nodes (bound > 0) after the step prev -> cur.
  void remember(const LoadStep& prev, const LoadStep& cur, const VecField& traction,
                const Field& bound);
  /// The memory bound in force (bytes per grid cell, kBytesPerCell unless set): a run whose
  /// rows are solved in sub-steps remembers every sub-step (bytes_per_cell in step_control.hpp).
  void set_bytes_per_cell(double bytes) { bytes_per_cell_ = bytes; }
  /// Entries remembered so far (a count that only grows), and the undoing of the newest
  /// `count` of them: a row solved again in other sub-steps forgets those of its first solve.
  std::size_t remembered() const { return remembered_; }
  void forget_newest(std::size_t count);
  bool empty() const { return entries_.empty(); }
  /// Doubles and node indices held.
  std::size_t stored() const { return stored_; }

  /// The whole memory as one flat list of numbers (the checkpoint's dataset `predictor`);
  /// empty when nothing is remembered.
  std::vector<double> flatten() const;
  /// The memory `flatten` wrote, for a grid of `cells` cells and `components` traction
  /// components; throws std::runtime_error saying what is wrong on any inconsistency.
  static CyclePredictor unflatten(const std::vector<double>& v, std::size_t cells, int components);
  /// On a grid distributed over ranks (slabs of whole rows j): the ranks' flat forms joined
  /// into the whole grid's (on rank 0, empty elsewhere), `offset` the first cell of this
  /// rank's slab; and the slab [offset, offset + cells) of a whole grid's flat form.
  static std::vector<double> gathered(const std::vector<double>& v, const Communicator& comm,
                                      Eigen::Index offset);
  static std::vector<double> sliced(const std::vector<double>& v, Eigen::Index offset,
                                    Eigen::Index cells);
  /// The reduction layer of a distributed grid: the memory bound and the sharing of node
  /// lists count every rank's nodes, so that all ranks keep the same entries (serial default).
  void set_communicator(const Communicator& comm) { comm_ = &comm; }

 private:
  struct Entry {
    LoadStep prev, cur;
    std::shared_ptr<const std::vector<Eigen::Index>> nodes;
    std::vector<std::vector<double>> values;  ///< per component, per node
  };
  void recount();
  std::deque<Entry> entries_;
  std::size_t stored_ = 0;  ///< doubles and indices held (a shared node list once)
  double bytes_per_cell_ = kBytesPerCell;
  std::size_t remembered_ = 0;
  VecField guess_;
  /// The node list whose values guess_ holds, zero elsewhere: a guess on the same list only
  /// overwrites its values (the clear of the whole grid was a pass per step).
  std::shared_ptr<const std::vector<Eigen::Index>> guess_nodes_;
  const Communicator* comm_ = &serial_communicator();
};

}  // namespace fretbem
