// Resolution and domain checks of a run: how many cells the slip zone
// spans, how much of the normal load sits on the outermost cells of a free-boundary grid, and
// what a sphere's Hertz solution predicts for both before a run.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "fretbem/contact/interface_state.hpp"
#include "fretbem/history/load_path.hpp"
#include "fretbem/history/observables.hpp"
#include "fretbem/scenario/scenario.hpp"

namespace fretbem {

/// Width of the slip zone in cells: slip nodes per unit length of the contact's edge,
/// N_slip / ((pi/4) E), E the number of cell edges between contact and non-contact nodes (the
/// staircase; pi/4 E estimates the length of the curve it digitises, Cauchy–Crofton). For an
/// annulus c < r < a it is (a^2 - c^2) / (2a), the width a - c when thin; 0 when nothing slips.
double slip_ring_cells(const StateField& state);
/// The same from the counts: N_slip slip nodes, E contact edges.
double slip_ring_width(long slip_nodes, long contact_edges);
/// Relative margin within which two computed loads (N) count as one load. A table reaches the
/// same |F_x| at several turning points (a sampled cosine: +Q and -Q every period), and the
/// force projection holds each to round-off only (1e-15 of the bound's sum); that round-off
/// follows the order of the sums, which the ranks of a distributed grid change. A choice
/// between such points taken on it (which turning point is the cycle's peak) then differed
/// between a serial run and the same run on two ranks. The margin is far above the round-off
/// and far below any load step a path resolves.
inline constexpr double kSameLoad = 1e-9;
/// Whether load `a` exceeds load `b` by more than kSameLoad |b| (a, b in N).
bool load_exceeds(double a, double b);
/// A turning point at which the tangential load peaks (|F_t| not below the previous step's
/// beyond kSameLoad): where the slip ring is measured. The end of a sine path, reached while
/// reloading through zero, is not one.
bool load_peak(const StepRecord& rec, const StepRecord& previous);
/// Contact nodes (state not open).
long contact_nodes(const StateField& state);
/// Share of the normal load carried by the outermost rows and columns of cells (0 ... 1).
double edge_load_share(const Field& pressure);

/// A free-boundary grid refuses a load share on its outermost cells above this unless
/// grid.allow_edge_contact = true (the answer then depends on the domain).
inline constexpr double kEdgeLoadShareLimit = 0.05;
/// The resolution report warns when the slip ring spans fewer cells than this (measured:
/// the Mindlin–Deresiewicz energy is within 0.5 % from two cells on, -2.5 % to -6.9 % below).
inline constexpr double kMinRingCells = 2.0;

/// Throws InputError when a sphere on a free-boundary grid carries more than kEdgeLoadShareLimit
/// of the load on its outermost cells and the scenario does not allow it; `where` names the
/// step. Rough, flat and file surfaces are not refused: their square domain is the nominal
/// contact (the paper's setting); the run report still gives their edge share.
void check_edge_contact(const Scenario& sc, double share, const std::string& where);

/// What Hertz and Mindlin–Deresiewicz predict for a sphere scenario (surface.type = sphere and
/// a constant normal load), before any solve.
struct SpherePrediction {
  double a = 0;              ///< Hertz contact radius (m)
  double a_over_h = 0;       ///< contact radius in cells
  double contact_nodes = 0;  ///< pi a^2 / h^2
  double ustar = 0;          ///< full-sliding shift mu delta E*/G* (m)
  double q = 0;              ///< tangential amplitude / (mu F_z) (1: gross slip)
  double ring_cells = 0;     ///< slip-ring width a (1 - (1 - q)^(1/3)) / h at the turning points
  int suggested_n = 0;       ///< smallest grid.n giving kMinRingCells at this grid.length
  double edge_share = 0;     ///< Hertz load share outside the circle inscribed in the domain
  double ramp_ratio = 0;     ///< U* / displacement amplitude of a displacement ramp (else 0)
};
std::optional<SpherePrediction> predict_sphere(const Scenario& sc);
/// The same at the largest normal load of the path (a table's Fz or delta column may raise it
/// above the constant load, or be the only one): what `fretbem check` reports, so that a
/// contact that grows past the domain later in the history is predicted before the run
/// refuses it at that step.
std::optional<SpherePrediction> predict_sphere(const Scenario& sc, const LoadPath& path);
/// The lines `fretbem check` prints for a prediction: facts, then warnings prefixed "warning:".
std::vector<std::string> describe(const SpherePrediction& p, const Scenario& sc);

}  // namespace fretbem
