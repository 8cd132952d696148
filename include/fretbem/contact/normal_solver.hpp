// NormalSolver: frictionless normal contact of a rigid indenter with height z (m, peaks
// positive) against the elastic half-space, by the Polonsky–Keer conjugate-gradient method
// (Polonsky & Keer, Wear 231, 1999), under force or indentation control.
#pragma once

#include <string>

#include "fretbem/core/solver_options.hpp"
#include "fretbem/elastic/grid.hpp"
#include "fretbem/elastic/half_space.hpp"

namespace fretbem {

struct NormalOptions {
  double tolerance = 1e-10;  ///< relative gap residual at which the solve stops
  int max_iterations = 2000;
  /// Preconditioned CG with M^-1 = S K^-1 S (S the contact set, K^-1 the Fourier inverse of
  /// the kernel): fewer iterations at the price of a second convolution per iteration;
  /// automatic: PreconditionDecision::for_grid.
  Precondition precondition = Precondition::automatic;
  /// Automatic preconditioning decided by the warm start's contact set
  /// (PreconditionDecision::for_set, as the tangential and stiffness solves) instead of the
  /// grid: for contacts of small patches, such as the Ciavarella–Jäger corrective problem's
  /// stick zone on a rough surface, where the second product per iteration does not pay.
  bool precondition_by_set = false;
};

/// Outcome of one normal solve. residual is the rms gap on the contact set plus the rms
/// penetration outside it, relative to the rms surface displacement on the contact set.
struct NormalResult {
  int iterations = 0;
  double residual = 0.0;
  bool converged = false;
  double force = 0.0;        ///< total normal force sum p h^2 (N)
  double indentation = 0.0;  ///< rigid approach delta (m), measured from first touch at z_max
  int convolutions = 0;      ///< FFT convolutions this solve used
};

class NormalSolver {
 public:
  /// Throws InputError when options.tolerance is below half_space.min_tolerance() (float FFTs).
  NormalSolver(HalfSpace& half_space, NormalOptions options = {});

  /// Force control: pressure p >= 0 (Pa) with sum p h^2 = force. p on entry is the warm start
  /// (ignored when empty, wrong-sized or all zero). Throws SolverError when not converged.
  NormalResult solve_force(const Field& z, double force, Field& p);
  /// Indentation control: pressure for a rigid approach delta (m) past first touch.
  NormalResult solve_indentation(const Field& z, double delta, Field& p);

  /// Surface displacement u_z (m) of the last solution.
  const Field& displacement() const { return u_; }
  const NormalOptions& options() const { return opt_; }
  const Grid& grid() const { return hs_.grid(); }

 private:
  class Iteration;  // the CG problem of one solve (normal_solver.cpp)

  NormalResult solve(const Field& z, bool force_control, double target, Field& p);
  void initial_guess(bool force_control, double target, Field& p) const;

  HalfSpace& hs_;
  NormalOptions opt_;
  Field h0_, u_, g_, t_, r_, z_;  // separation z_max - z, displacement, gap, direction, its image
};

}  // namespace fretbem
