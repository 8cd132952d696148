// Per-cycle results of a load history, the one home of what a run measures per cycle: a
// stepped run's (the rows of DIR/cycles.csv, also the Python stepper's `cycles`: energy
// dissipated, loop area, amplitudes, k_x and slip at the turning points, the resolution at the
// load peaks, accumulated from the steps' records) and a wear run's simulated cycles (energy,
// stick area, indentation, contact radius, peak pressure and slip, from the steps' records and
// states; wear/cycles.cpp adds the worn depth).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "fretbem/contact/interface_state.hpp"
#include "fretbem/history/load_path.hpp"
#include "fretbem/history/observables.hpp"
#include "fretbem/parallel/communicator.hpp"

namespace fretbem {

/// One load cycle (period 1 in time). Energies in J, forces in N, shifts in m, k_x in N/m,
/// areas in m^2; the resolution in cells of the grid.
struct CycleRow {
  int cycle = 0;
  int steps = 0;
  double dissipated_energy = 0;  ///< sum of the nodal dissipation over the cycle's steps
  double loop_area = 0;          ///< closed integral of F . dU (trapezoid, x and y)
  double Fx_amplitude = 0, Ux_amplitude = 0;  ///< half the peak-to-peak range
  /// k_x at the turning points of largest and smallest F_x; a cycle without such a turning
  /// point (a table that ends or starts mid-way) takes the step of largest/smallest F_x.
  double kx_at_max = 0, kx_at_min = 0;
  double slip_area_at_peak = 0;  ///< slip area at the turning point of largest |F_x|
  /// At the cycle's load peaks (the narrowest ring), else at its last step: slip-ring width
  /// (cells), contact nodes and the equivalent contact radius sqrt(A/pi)/h (a/h of a sphere).
  double slip_ring_cells = 0;
  long contact_nodes = 0;
  double a_over_h = 0;
  /// Sum of the cycle's step_error (StepRecord): the embedded estimate of its dissipation's
  /// relative error; 0 with load.tolerance = 0.
  double step_error = 0;

  /// Column names of DIR/cycles.csv, in the order of values().
  static const std::vector<std::string>& columns();
  std::vector<double> values() const;
};

/// Gathers the steps of a path into cycles. A step's increment belongs to the cycle that
/// contains its time interval (t_{k-1}, t_k]. Ramps and normal-only paths have no cycles.
class CycleAccumulator {
 public:
  /// h: grid spacing (m), for a_over_h.
  CycleAccumulator(PathType path, double h);
  /// Adds the next step; returns the cycle it closed, if any (the previous one).
  std::optional<CycleRow> add(const StepRecord& rec);
  /// Closes the cycle in progress (the path ended), if any.
  std::optional<CycleRow> finish();

 private:
  void start_cycle(int cycle);
  void track_resolution(const StepRecord& r);
  void track_extremes(const StepRecord& r);
  CycleRow row() const;

  bool cyclic_;
  double h_;
  bool have_prev_ = false;
  StepRecord prev_;
  bool in_cycle_ = false;  // cycle_ holds a cycle (table times may be negative: no sentinel)
  int cycle_ = 0;
  double diss0_ = 0, loop_ = 0, fmin_ = 0, fmax_ = 0, umin_ = 0, umax_ = 0;
  // kx at the extreme-F_x turning points; kx at the extreme-F_x steps for a cycle without one.
  double k_at_max_ = 0, k_at_min_ = 0, slip_at_peak_ = 0, peak_ = -1;
  double k_any_max_ = 0, k_any_min_ = 0;
  bool turn_max_ = false, turn_min_ = false;
  double ring_ = -1, ring_radius_ = 0;
  long ring_nodes_ = 0;
  bool ring_at_peak_ = false;
  int steps_ = 0;
  double step_error_ = 0;
};

/// What one simulated wear cycle measures from its steps. Energies in J, areas in m^2,
/// lengths in m, pressures in Pa.
struct CycleMeasures {
  double energy = 0.0;          ///< dissipated over the cycle
  double stick_area = 0.0;      ///< smallest stick area of its steps (at its peak load)
  double delta = 0.0;           ///< indentation at the period's end (phase 0)
  double contact_radius = 0.0;  ///< sqrt(A / pi) of the contact area A there
  double peak_pressure = 0.0;   ///< max p there
  double max_slip = 0.0;        ///< largest slip path growth of a node in contact
};

/// Accumulates the CycleMeasures of a simulated wear cycle step by step.
class CycleMeter {
 public:
  /// dissipation0: the cumulative dissipation (J) before the cycle; slip_path0: the slip
  /// paths (m) before it (this rank's slab on a distributed grid, whose maxima are taken
  /// over `comm`'s ranks).
  CycleMeter(double dissipation0, Field slip_path0,
             const Communicator& comm = serial_communicator());
  /// Adds a step at load phase `phase` (time in periods) with its record and the state after.
  void add(const StepRecord& rec, const InterfaceState& state, double phase);
  /// The cycle's measures: `dissipation` the cumulative dissipation (J) after its last step,
  /// `state` the state after it.
  CycleMeasures finish(double dissipation, const InterfaceState& state) const;

 private:
  double largest(const Field& x) const;

  double dissipation0_;
  Field slip_path0_;
  const Communicator* comm_;
  CycleMeasures m_;
  double contact_ = 0.0;
  bool at_phase0_ = false;
};

}  // namespace fretbem
