// Pre-flight checks of a prepared model (see preflight.hpp for what and why one path).
#include "fretbem/history/preflight.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>

#include "fretbem/core/errors.hpp"
#include "fretbem/core/format.hpp"
#include "fretbem/core/input_warning.hpp"

namespace fretbem {

namespace {

// Past this many full-sliding shifts U* a displacement-controlled loop is gross sliding through
// and through: the contact's elastic displacement (at most about U*) is then below 1e-6 of the
// imposed shift, which keeps it two decades above the default relative tolerance (1e-8) of the
// tangential residual; much further and the solve no longer resolves it. Measured without this
// bound: 1e150 m gives "residual -nan", 1e160-1e300 m exit 0 with Fx = Ux = 0 on every row.
constexpr double kMaxShiftOverFullSliding = 1e6;

void check_periodic_indentation(const Scenario& sc, const LoadPath& path) {
  if (!sc.grid.periodic) return;
  for (const auto& s : path.steps)
    if (!s.normal.force_control)
      throw InputError(
          "grid.periodic = true with indentation control (load.indentation or a table "
          "'delta' column): a periodic half-space has no finite mean displacement, so "
          "use load.normal_force or an Fz column");
}

void check_wear_path(const Scenario& sc) {
  if (sc.wear.law != WearLaw::none && sc.load.path != PathType::sine &&
      sc.load.path != PathType::table)
    throw InputError(
        "wear.law: a wear run needs a periodic load (load.path = sine, or a table holding one "
        "period)");
}

// Table forces are in N; force control cannot go past full sliding (the solver would refuse it
// at the step, exit 3, after the earlier steps ran). Known before any solve when Fz is given.
void check_table_friction(const Scenario& sc, const LoadPath& path) {
  if (sc.load.path != PathType::table) return;
  const double mu = sc.material.mu;
  for (const auto& s : path.steps) {
    if (s.control != Control::force || s.relative || !s.normal.force_control) continue;
    const double limit = mu * s.normal.value;
    if (s.target.norm() < limit) continue;
    std::ostringstream msg;
    msg << sc.load.table.string() << ": at time " << format_number(s.time)
        << " the tangential force " << format_number(s.target.norm())
        << " N is not below mu Fz = " << format_number(limit)
        << " N (material.mu = " << format_number(mu)
        << "): force control cannot go past full sliding; use Ux/Uy columns";
    throw InputError(msg.str());
  }
}

// Small-strain bounds (the model is linear elasticity): a normal force that strains even the
// whole L x L domain by more than 1 (F / (E* L^2) >= 1), or an indentation deeper than the
// domain is wide, cannot be a small-strain contact. These also keep the pressures and
// displacements the solver forms within the range its arithmetic carries.
// The key or table column a normal load came from: a table's Fz must not be reported as
// load.normal_force, which the scenario did not set.
std::string normal_load_source(const Scenario& sc, bool force) {
  const bool from_table = force ? !sc.load.normal_force : !sc.load.indentation;
  if (from_table && sc.load.path == PathType::table)
    return sc.load.table.string() + (force ? ": Fz" : ": delta");
  return force ? "load.normal_force" : "load.indentation";
}

void check_strain(const Scenario& sc, const ContactScales& s) {
  const double L = sc.grid.h * sc.grid.nx, area = L * sc.grid.h * sc.grid.ny;
  if (s.max_normal_force / (s.E_star * area) >= 1.0) {
    std::ostringstream msg;
    msg << normal_load_source(sc, true) << ": " << format_number(s.max_normal_force)
        << " N over the grid.length^2 domain is a mean pressure above E* = "
        << format_number(s.E_star) << " Pa (strain above 1): raise material.E or grid.length, "
        << "or lower the force";
    throw InputError(msg.str());
  }
  if (s.max_indentation >= L)
    throw InputError(normal_load_source(sc, false) + ": " + format_number(s.max_indentation) +
                     " m is not below grid.length = " + format_number(L) +
                     " m (strain above 1): check the unit (m)");
}

// The key or table columns a tangential shift came from.
std::string shift_source(const Scenario& sc) {
  return sc.load.path == PathType::table ? sc.load.table.string() + ": Ux/Uy"
                                         : "load.displacement_amplitude";
}

void check_shift(const Scenario& sc, const ContactScales& s) {
  if (s.max_tangential_shift <= kMaxShiftOverFullSliding * s.full_sliding_shift) return;
  throw InputError(shift_source(sc) + ": a shift of " + format_number(s.max_tangential_shift) +
                   " m is over 1e6 times the full-sliding shift U* = mu delta E*/G* = " +
                   format_number(s.full_sliding_shift) +
                   " m: past that the solver cannot resolve the contact's elastic response; "
                   "the loop is pure gross sliding (check the unit: m)");
}

std::string contact_radius_text(const Scenario& sc, const ContactScales& s) {
  return (sc.surface.type == SurfaceType::sphere ? "the Hertz contact radius a = "
                                                 : "half the domain side, a = ") +
         format_printf("%.4g", s.contact_radius) + " m";
}

void check_small_slip(const Scenario& sc, const ContactScales& s) {
  if (!(s.contact_radius > 0.0)) return;
  const double radii = s.max_tangential_shift / s.contact_radius;
  if (radii <= kWarnShiftOverContactRadius) return;
  const std::string what = shift_source(sc) + ": a shift of " +
                           format_number(s.max_tangential_shift) + " m is " +
                           format_printf("%.3g", radii) + " times " + contact_radius_text(sc, s) +
                           "; the model keeps the contact geometry "
                           "fixed (small slip)";
  if (radii <= kMaxShiftOverContactRadius || sc.load.allow_large_shift) {
    input_warning(what + ", which such a shift strains (results lose accuracy)");
    return;
  }
  throw InputError(what +
                   ", which a shift past one contact radius breaks: check the unit (m), "
                   "or set load.allow_large_shift = true to run anyway");
}

}  // namespace

ContactScales contact_scales(const Scenario& sc, const LoadPath& path, const Field& surface) {
  ContactScales s;
  s.E_star = sc.material.E_star();
  s.G_star = sc.material.G_star();
  for (const auto& st : path.steps) {
    (st.normal.force_control ? s.max_normal_force : s.max_indentation) =
        std::max(st.normal.force_control ? s.max_normal_force : s.max_indentation, st.normal.value);
    if (st.control == Control::displacement)
      s.max_tangential_shift = std::max(s.max_tangential_shift, st.target.norm());
  }
  const double L = sc.grid.h * sc.grid.nx;
  double delta = std::max(s.max_indentation, s.max_normal_force / (s.E_star * L));
  if (sc.surface.type == SurfaceType::sphere && s.max_normal_force > 0.0) {
    const double F = s.max_normal_force, R = sc.surface.radius;
    s.hertz_a = closed_forms::hertz_contact_radius(F, R, s.E_star);
    s.hertz_p0 = closed_forms::hertz_peak_pressure(F, s.hertz_a);
    s.hertz_delta = closed_forms::hertz_approach(s.hertz_a, R);
    delta = std::max(delta, s.hertz_delta);
  }
  if (surface.size() > 0) delta = std::max(delta, surface.maxCoeff() - surface.minCoeff());
  s.normal_displacement = delta;
  // The approach is known before a solve for a sphere (Hertz) or under indentation control;
  // elsewhere the largest displacement scale bounds it.
  const double known = std::max(s.max_indentation, s.hertz_delta);
  s.approach_known = known > 0.0;
  s.full_sliding_shift =
      full_sliding_shift(sc.material.mu, s.approach_known ? known : delta, s.E_star, s.G_star);
  if (sc.surface.type == SurfaceType::sphere)
    s.contact_radius = std::max(s.hertz_a, std::sqrt(sc.surface.radius * s.max_indentation));
  else
    s.contact_radius = 0.5 * std::min(L, sc.grid.h * sc.grid.ny);
  return s;
}

// Heights of a file surface: the bound of every dimensional input (scenario Reader::magnitude).
void check_heights(const Scenario& sc, const Field& surface) {
  if (surface.size() == 0) return;
  const double top = surface.cwiseAbs().maxCoeff();
  if (top <= 1e100) return;
  throw InputError(
      (sc.surface.type == SurfaceType::file ? sc.surface.file.string() : std::string("surface")) +
      ": heights up to " + format_number(top) +
      " m are outside the range the solver's arithmetic can carry (1e100)");
}

void check_before_solve(const Scenario& sc, const LoadPath& path, const Field& surface) {
  check_heights(sc, surface);  // a surface handed in (Python's Model) met no make_surface
  check_periodic_indentation(sc, path);
  check_wear_path(sc);
  check_table_friction(sc, path);
  const ContactScales s = contact_scales(sc, path, surface);
  check_strain(sc, s);
  check_shift(sc, s);
  check_small_slip(sc, s);
}

}  // namespace fretbem
