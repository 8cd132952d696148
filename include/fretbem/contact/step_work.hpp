// StepWork: the frictional work of one load step per node and the quadrature of the Coulomb
// bound along the step's slip that gives it. The dissipation and both wear laws (wear_law/law.hpp)
// take this one quadrature, so that with a constant mu Archard's worn depth is (k / mu) x the
// work and the energy law's alpha x the work, to round-off.
#pragma once

#include <span>

#include "fretbem/contact/interface_state.hpp"

namespace fretbem {

/// One step's slip and the bound along it, per node.
struct StepWork {
  Field slip;      ///< slip length |s| of the step (m)
  Field pressure;  ///< the pressure along the slip, by the bound's quadrature (Pa)
  Field work;      ///< frictional work: the bound along the slip times |s| (J/m^2), >= 0
};

/// The step before, for the three-point rule of a node slipping through both steps on a path
/// that is C1 between them: per node the bound and pressure changes over it (Pa) and its slip
/// length (m) where the node slipped at both its ends (0 elsewhere: the rule does not apply);
/// its span h0 and the current step's h1 (any one unit of time).
struct StepBefore {
  const Field& bound_change;
  const Field& pressure_change;
  const Field& slip;
  double span = 0.0, span_next = 0.0;
};

/// The start of a step whose bound moved (a normal re-solve): the bound and pressure before
/// it, and the node states and tractions the previous step ended with.
struct StepStart {
  const Field& bound;        ///< g0 (Pa)
  const Field& pressure;     ///< p0 (Pa)
  const StateField& state;   ///< states of the previous step
  const VecField& traction;  ///< tau0 (Pa), operator components
  /// Fraction theta of the step at which each node losing contact in it opened (contact_entry:
  /// loss_fraction); null: at the step's end (theta = 1).
  const Field* loss = nullptr;
  /// c_tt: a node's tangential displacement per unit traction on its own cell (m/Pa).
  double tangential_self = 0.0;
  /// The step before, where the path is C1 at this step's start (load.interpolation = cubic);
  /// null: the two-point rules alone.
  const StepBefore* before = nullptr;
};

/// The weights (w0, w1, wd) of node k's bound (and pressure) at the step's start and end and of
/// its change over the step before, along its slip of length `len`, by the rules of step_work
/// below: its work is (w0 g0 + w1 g1 + wd (g0 - g_-1)) len.
struct BoundWeights {
  double start = 0.0, end = 0.0, change_before = 0.0;
};
BoundWeights bound_weights(const StepStart* start, const InterfaceState& end, const Field& bound,
                           const VecField& s, double len, Eigen::Index k);

/// The pressure along the slip and the work of a step that ended in `end` (classified, bound
/// g1 = `bound`) with slip increments `s` (m, operator components); `out.slip` holds every
/// node's slip length |s| on entry. A slipping node carries its bound and its traction is
/// parallel to its slip, so its work is the integral of g |ds|; with the bound and the slip
/// linear in the step:
/// - bound fixed (start null), or the node starts to slip in the step: g1 |s|;
/// - slipping before and after the step's start: trapezoid (g0 + g1)/2 |s|, second order;
///   with the step before (start.before) where the node slipped through it too, the
///   three-point rule: the trapezoid plus its error for a bound quadratic and a slip rate
///   linear in time across both steps (spans h0, h1),
///   c (dg0 |s| - dg1 |s0|), c = h1^2 / (6 h0 (h0 + h1)), dg the bound's change over a step
///   and |s0| the slip over the step before (exact for that pair; third order), i.e. the
///   weights (1/2 + c r, 1/2 - c r, c) with r = |s0| / |s|. A rule whose mean bound comes out
///   negative (a bound falling steeply to zero) gives way to the trapezoid;
/// - losing contact in the step (g1 = 0 < g0) at the fraction theta of it: its traction relaxes
///   with the bound from tau0 = g0 e to zero over [0, theta] while it slips along e. Its slip
///   there is its free motion f (the slip it would make carrying no traction, linear in the
///   step: f = s - c_tt tau0 over the whole step) until theta plus its own elastic release
///   c_tt g0, so the work is g0/2 (theta f.e + c_tt g0) = (theta tau0.s + (1 - theta) c_tt g0^2)/2;
///   the displacement after the node opened is free motion, not slip. At most g0 |s| / 2; a
///   slip against tau0 needs the traction reversed first, elastically, while the bound falls
///   to zero, and counts nothing;
/// - otherwise (stick, open, on the bound without slipping): nothing.
/// The pressure along the slip takes the same weights on p0 and p1.
void step_work(const StepStart* start, const InterfaceState& end, const Field& bound,
               const VecField& s, StepWork& out);
/// The same on the listed nodes only, for a step whose bound did not move (no start): off
/// them the node is open, so its pressure along the slip and its work are zero, and `out`'s
/// pressure and work must already hold those zeros (the caller's contract; sized like bound).
void step_work(const InterfaceState& end, const Field& bound, const VecField& s, StepWork& out,
               std::span<const Eigen::Index> nodes);

}  // namespace fretbem
