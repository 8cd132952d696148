// WearPreconditioner: the linearised per-cycle wear map, used to precondition the Newton–Krylov
// iterations of the implicit wear integrator.
//
// The wear of a cycle is w = d ⊙ p(W): the pressure p of the surface z0 - W times the wear per
// unit pressure d = w / p of each node in contact (k S for Archard with S the slip path of the
// cycle; about alpha mu S for the energy law). The stiff part of dw/dW is the pressure's
// response, with the slip frozen: removing v from the contact nodes changes the pressure by q,
//   C q = dδ 1 - v  on the contact set A,  q = 0 off A,  Σ q = 0 (force control; dδ = 0 under
//   indentation control),
// with C the normal influence operator (m/Pa). The Newton matrix of an implicit step with
// coefficient gamma is P = I - gamma J, J v = d ⊙ q(v). P x = b is solved exactly through
//   (C_A + gamma D) q = dδ 1 - b_A,  x = b + gamma D q  (D = diag d),
// an SPD system on A (two CG solves: one for the right-hand side, one cached for 1 under force
// control). Its eigenvalues near gamma d K_max are the ones that cap explicit steps at
// 1 / (k s K_max): with P the Krylov solver sees them removed.
//
// How exactly: a CG residual r of the first system, (C_A + gamma D) q = dδ 1 - b_A + r, moves x
// by gamma D (C_A + gamma D)^-1 r, whose eigenvalues lie in [0, 1) (D >= 0, C_A SPD): x is off by
// about |r| (m). A Newton correction needs no more than the accuracy ARKODE asks of its linear
// solves (its `delta`, 0.05 times the Newton tolerance in the error weights' units), and the
// frozen slip is a larger error of P itself, so solve() stops there.
#pragma once

#include "fretbem/elastic/grid.hpp"
#include "fretbem/elastic/half_space.hpp"

namespace fretbem {

class WearPreconditioner {
 public:
  /// tolerance: relative residual of the inner CG solves.
  WearPreconditioner(HalfSpace& half_space, bool force_control, double tolerance = 1e-8);

  /// Linearises at a cycle with pressure p (Pa) and worn depth per cycle w (m): A = {p > 0},
  /// d = w / p on A (m/Pa per cycle).
  void setup(const Field& pressure, const Field& wear_per_cycle);
  /// x = P^-1 b for P = I - gamma J (gamma in cycles), the inner CG residual at most
  /// max(tolerance x |b_A|, residual) (2-norm over the grid, m; 0: the relative tolerance
  /// alone). Throws SolverError if an inner CG solve does not converge.
  void solve(const Field& b, double gamma, Field& x, double residual = 0.0);

  bool ready() const { return ready_; }
  /// The last solve's q: the pressure change (Pa) of the linearised cycle when the worn depth
  /// moves by its x (zero off the contact set). Empty before the first ready solve.
  const Field& pressure_change() const { return q_; }
  /// Inner CG iterations (= convolutions) since construction.
  long iterations() const { return iterations_; }

 private:
  /// (C_A + gamma D) q = r on A to a residual of at most max(tolerance |r_A|, share |r_A|),
  /// Jacobi-preconditioned CG; q = 0 off A.
  void cg(const Field& r, double gamma, Field& q, double share);
  /// The grid's reduction layer: fields are this rank's slab, sums over all ranks.
  const Communicator& comm() const { return hs_.communicator(); }

  HalfSpace& hs_;
  bool force_control_;
  double tol_;
  bool ready_ = false;
  Eigen::ArrayXXd mask_;  // 1 on A
  Field d_;               // wear per unit pressure, 0 off A
  double cached_gamma_ = -1.0, cached_share_ = 0.0;
  Field ones_solution_;                 // (C_A + gamma D)^-1 1_A for cached_gamma_
  Field q_, diag_, r_, z_, s_, t_, u_;  // work fields, kept between solves
  long iterations_ = 0;
};

}  // namespace fretbem
