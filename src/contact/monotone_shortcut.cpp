#include "fretbem/contact/monotone_shortcut.hpp"

#include <sstream>

#include "fretbem/core/errors.hpp"

namespace fretbem {

namespace {

ShortcutResult assemble(const Field& p, const Field& p_star, const NormalResult& nr, double delta,
                        double mu, double ratio, double area) {
  // The corrective pressure p* (zero when nothing sticks), then tau = mu (p - p*).
  ShortcutResult r;
  r.traction = mu * (p - p_star);
  r.force = r.traction.sum() * area;
  r.shift = mu * ratio * (delta - nr.indentation);  // eq. 19: d* = d - G* u / (E* mu)
  r.corrective = nr;
  return r;
}

}  // namespace

ShortcutResult ciavarella_jaeger_force(NormalSolver& normal, const Field& z, const Field& p,
                                       double Fz, double delta, double mu, double ratio, double Ft,
                                       const Field* p_star_start) {
  if (!(Ft >= 0.0 && Ft < mu * Fz)) {
    std::ostringstream msg;
    msg << "monotone shortcut: tangential force " << Ft << " N outside [0, mu F_z = " << mu * Fz
        << " N)";
    throw SolverError(msg.str());
  }
  // Warm start: the previous p*, or p (the corrective solution is close to a scaled p).
  Field p_star = p_star_start ? *p_star_start : p;
  const NormalResult nr = normal.solve_force(z, Fz - Ft / mu, p_star);  // eq. 18
  return assemble(p, p_star, nr, delta, mu, ratio, normal.grid().cell_area());
}

ShortcutResult ciavarella_jaeger_shift(NormalSolver& normal, const Field& z, const Field& p,
                                       double delta, double mu, double ratio, double U,
                                       const Field* p_star_start) {
  Field p_star = p_star_start ? *p_star_start : p;
  const double d_star = delta - U / (mu * ratio);  // eq. 19
  const NormalResult nr = normal.solve_indentation(z, d_star, p_star);
  ShortcutResult r = assemble(p, p_star, nr, delta, mu, ratio, normal.grid().cell_area());
  r.shift = U;  // imposed (also past full sliding, where p* = 0)
  return r;
}

}  // namespace fretbem
