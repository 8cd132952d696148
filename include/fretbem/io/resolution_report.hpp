// The run's resolution and domain report: slip-ring width in cells at the load peaks in partial
// slip (the end of a ramp, the turning points of a cycle), or that the whole contact slides
// there; contact nodes, a/h, the load share on the edge of a free-boundary grid, and a
// displacement ramp that ends below full sliding. Facts on stdout, warnings on stderr.
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
  void resolution_lines(const Scenario& sc);
  void keep_peak(const StepRecord& r, double h);

  /// Narrowest slip ring at a load peak in partial slip (cells); -1: none seen.
  double ring_ = -1;
  /// A load peak at which the whole contact slides (no stick node): a ring width there only
  /// restates the contact's size.
  bool sliding_peak_ = false;
  /// A load peak reached under a rising normal load at which no node slips: full stick,
  /// whatever the grid.
  bool stuck_peak_ = false;
  long nodes_ = 0;
  double radius_cells_ = 0, edge_share_ = 0;
  StepRecord last_;
  std::string summary_;
  std::vector<std::string> warnings_;
};

}  // namespace fretbem
