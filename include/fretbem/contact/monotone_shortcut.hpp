// Monotone shortcut: the Ciavarella–Jäger principle (Ciavarella 1998; Jäger 1998; paper
// eqs. 16–19). For a tangential load rising monotonically from zero at constant normal load
// under the Cattaneo–Mindlin analogy, the traction is the superposition of two normal
// solutions, tau = mu p(F_z) - mu p*(Q*), Q* = F_z - F_t/mu, and the rigid shift is
// U = mu (E*/G*) (delta - delta*). Exact on the discrete grid too; a fast path for monotone
// scenes and a cross-check of the incremental solver.
#pragma once

#include "fretbem/contact/normal_solver.hpp"

namespace fretbem {

struct ShortcutResult {
  Field traction;           ///< traction magnitude along the load direction (Pa)
  double shift = 0.0;       ///< rigid tangential shift along the load direction (m)
  double force = 0.0;       ///< tangential force (N)
  NormalResult corrective;  ///< the normal solve of the corrective problem
};

/// Force control: tangential force F_t (0 <= F_t < mu F_z) on the normal solution p
/// (force F_z, indentation delta) of surface z. Uses `normal` for the corrective solve,
/// warm-started from `p_star_start` when given (the previous step's p* on a monotone segment:
/// Q* moves little per step), else from p.
ShortcutResult ciavarella_jaeger_force(NormalSolver& normal, const Field& z, const Field& p,
                                       double Fz, double delta, double mu, double ratio, double Ft,
                                       const Field* p_star_start = nullptr);
/// Displacement control: rigid shift U >= 0; past full sliding (delta* <= 0) the whole contact
/// slips and tau = mu p.
ShortcutResult ciavarella_jaeger_shift(NormalSolver& normal, const Field& z, const Field& p,
                                       double delta, double mu, double ratio, double U,
                                       const Field* p_star_start = nullptr);

}  // namespace fretbem
