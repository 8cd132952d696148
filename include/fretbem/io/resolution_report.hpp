// The run's resolution and domain report (issues 17 §3 and 18): slip-ring width in cells at the
// turning points, contact nodes, a/h, the load share on the edge of a free-boundary grid, and
// a displacement ramp that ends below full sliding. Facts on stdout, warnings on stderr.
#pragma once

#include <string>
#include <vector>

#include "fretbem/history/stepper.hpp"

namespace fretbem {

class ResolutionReport final : public Observer {
 public:
  void on_step(const StepRecord& rec, const InterfaceState& state, const Model& model) override;
  void on_finish(const InterfaceState& state, const Model& model) override;
  /// The summary line (stdout) and the warnings (stderr) of the finished run.
  std::string summary() const { return summary_; }
  const std::vector<std::string>& warnings() const { return warnings_; }

 private:
  double ring_ = -1;  ///< narrowest slip ring at a turning point (cells); -1: none seen
  long nodes_ = 0;
  double radius_cells_ = 0, edge_share_ = 0;
  StepRecord last_;
  std::string summary_;
  std::vector<std::string> warnings_;
};

}  // namespace fretbem
