// Observables: the per-step scalars of the time series (README "Time series").
#pragma once

#include <span>
#include <string>
#include <vector>

#include "fretbem/contact/interface_state.hpp"

namespace fretbem {

struct StepRecord {
  int step = 0;
  double time = 0.0;
  int cycle = 0;
  double Fz = 0, delta = 0, Fx = 0, Fy = 0, Ux = 0, Uy = 0;  // N, m
  double contact_area = 0, stick_area = 0, slip_area = 0;    // m^2
  double Fx_stick = 0;                                       ///< x force carried by stick nodes (N)
  double kx = 0;           ///< differential tangential stiffness dFx/dUx (N/m); NaN when off
  double dissipation = 0;  ///< cumulative sum tau . s h^2 (J)
  double wear_volume = 0;  ///< cumulative worn volume (m^3)
  int normal_iterations = 0, tangential_iterations = 0;
  double normal_residual = 0, tangential_residual = 0;
  int convolutions = 0;  ///< FFT convolutions this step used
  bool turning = false;  ///< turning point of the load path
  /// Part of stick_area on its Coulomb bound without slipping this step (m^2).
  double stuck_at_bound_area = 0;
  double slip_ring_cells = 0;  ///< width of the slip zone in cells (resolution.hpp)
  long contact_nodes = 0;      ///< nodes in contact
  double edge_load_share = 0;  ///< share of F_z on the outermost cells (0 on periodic grids)
  /// solver.coupling = coupled (beta != 0): normal/tangential alternations this step, and the
  /// larger relative change of pressure or traction in the last one; 0 otherwise.
  int coupling_iterations = 0;
  double coupling_residual = 0;
  /// load.tolerance > 0: the embedded estimate of the row's error in the dissipation
  /// (history/step_control.hpp), relative to the dissipation per period, summed over its
  /// sub-steps; 0 where nothing was estimated.
  double step_error = 0;
  /// Solves of the row: its sub-steps (load.substeps, load.tolerance), those of a row solved
  /// again included; 1 for a row solved whole. Not a column: what the cost estimate's
  /// calibration counts its convolutions over.
  int substeps = 1;

  /// Column names, in the order of values(); the first 18 are the README contract.
  static const std::vector<std::string>& columns();
  std::vector<double> values() const;
  /// Inverse of values() (a row read back from timeseries.csv).
  static StepRecord from_values(const std::vector<double>& v);
};

/// A contact that does not change over a run's steps: its nodes (this rank's slab indices,
/// ascending; every other node open) and its cell edges (slab_measures.hpp contact_edges).
struct FixedContact {
  std::span<const Eigen::Index> nodes;
  long edges = 0;
};

/// Fills the areas, Fx_stick, slip_ring_cells and contact_nodes of a record from a classified
/// interface state (x components from the operator's basis); on a distributed grid `s` holds
/// this rank's slabs and the record the whole grid's values (hs's communicator). With `fixed`
/// the nodes are counted on its list (the open nodes off it count nothing) and the ring's
/// perimeter is its edges: the same numbers without passes over the whole grid.
void measure_areas(const InterfaceState& s, const TangentialOperator& op, const HalfSpace& hs,
                   StepRecord& r, const FixedContact* fixed = nullptr);

}  // namespace fretbem
