// Friction laws: the Coulomb bound g_i = mu_i p_i of every node (docs/architecture.md, "Laws are
// small interfaces"). The stepper asks the law for the bound before each step and keeps it fixed
// within each solve, so every increment stays the convex problem of docs/algorithms.md; the law
// may change mu_i between steps from the node's history, lower it where a node slips
// (after_slip) or set the bound the step ends on from its slip (end_bound), the increment then
// solved again. Nothing else knows which law is in use.
#pragma once

#include <algorithm>
#include <memory>

#include "fretbem/contact/interface_state.hpp"
#include "fretbem/scenario/scenario.hpp"

namespace fretbem {

/// One step's slip, per node, split by the quadrature of the bound along it
/// (contact/step_work.hpp): the node's frictional work in the step is
/// start_work + mu_1 end_pressure_slip, mu_1 its coefficient at the step's end.
struct StepSlip {
  Field path;               ///< |s| of the nodes that slip in the step, 0 elsewhere (m)
  Field start_work;         ///< w0 g0 |s|: the share of the bound at the step's start (J/m^2)
  Field end_pressure_slip;  ///< w1 p1 |s| (N/m)
};

class FrictionLaw {
 public:
  virtual ~FrictionLaw() = default;
  /// The bound g = mu p (Pa) of every node for the next step, from the state after the last
  /// (pressure of this step, slip history of the previous ones).
  virtual void bound(const InterfaceState& state, Field& g) const = 0;
  /// True when mu depends on the history: the bound is then re-evaluated before every step.
  virtual bool evolves() const = 0;
  /// The smallest mu the law can reach (force-controlled paths must stay below it).
  virtual double min_mu() const = 0;
  /// Within a tangential increment: `slipped` is 1 where a node slipped in it so far, 0
  /// elsewhere. A law whose mu changes the moment a node slips (static/kinetic) lowers g there
  /// and returns true; the increment is then solved again with the lower bound. g only falls,
  /// so the re-solves end.
  virtual bool after_slip(const InterfaceState& /*state*/, const Field& /*slipped*/,
                          Field& /*g*/) const {
    return false;
  }
  /// After a tangential increment, for a law whose mu follows the node's history within the
  /// step (evolving): g = mu_1 p_1, the bound at the step's end given the step's slip (the
  /// stepper solves the increment again with it until it stops moving). `state` holds the
  /// step's end pressure p_1 and the history at its start.
  virtual void end_bound(const InterfaceState& /*state*/, const StepSlip& /*step*/,
                         Field& /*g*/) const {}
  /// True for laws with end_bound: their bound at a step's end is solved for with the step.
  virtual bool settles_within_step() const { return false; }
};

/// Coulomb with constant mu (the default): g = mu p.
class ConstantFriction final : public FrictionLaw {
 public:
  explicit ConstantFriction(double mu) : mu_(mu) {}
  void bound(const InterfaceState& state, Field& g) const override;
  bool evolves() const override { return false; }
  double min_mu() const override { return mu_; }

 private:
  double mu_;
};

/// Static/kinetic: mu_k at nodes that slipped in the last step or slip in this one (from the
/// moment they slip: after_slip) and at their four grid neighbours (the slip front), mu_s
/// elsewhere. The front takes mu_k because the continuum traction is continuous across a
/// moving slip front (a jump would make it singular, past any bound): the stick side of the
/// front carries mu_k p, so a front node held to mu_s is a grid artefact that enlarges the stick
/// zone by O(sqrt h) (docs/algorithms.md, "Static/kinetic friction").
class StaticKineticFriction final : public FrictionLaw {
 public:
  StaticKineticFriction(double mu_static, double mu_kinetic, bool periodic)
      : ms_(mu_static), mk_(mu_kinetic), periodic_(periodic) {}
  void bound(const InterfaceState& state, Field& g) const override;
  bool evolves() const override { return true; }
  double min_mu() const override { return std::min(ms_, mk_); }
  bool after_slip(const InterfaceState& state, const Field& slipped, Field& g) const override;

 private:
  /// g for the nodes marked kinetic (1) and the pressure p.
  Field kinetic_bound(const Field& kinetic, const Field& p) const;
  double ms_, mk_;
  bool periodic_;  ///< neighbours wrap around the grid's edges
};

/// Running-in: mu = mu_0 + (mu_final - mu_0) (1 - exp(-X / scale)) per node, X its accumulated
/// dissipated energy density or slip path (a saturating law; Fouvry et al. report mu rising
/// from ~0.2 to ~0.8 over the first hundreds to thousands of fretting cycles). A step ends on
/// mu(X_1), X_1 the history at its end with the step's work by the trapezoid of the bound
/// (implicit: second order in the step, docs/algorithms.md, "Evolving friction").
class EvolvingFriction final : public FrictionLaw {
 public:
  EvolvingFriction(double mu0, const FrictionSpec& spec) : mu0_(mu0), spec_(spec) {}
  void bound(const InterfaceState& state, Field& g) const override;
  bool evolves() const override { return true; }
  double min_mu() const override { return std::min(mu0_, spec_.mu_final); }
  void end_bound(const InterfaceState& state, const StepSlip& step, Field& g) const override;
  bool settles_within_step() const override { return true; }

 private:
  double mu(double x) const;
  /// X_1 = X_0 + a + b mu(X_1) (the work's trapezoid) for the dissipation variable.
  double dissipation_at_end(double x0, double a, double b) const;
  double mu0_;
  FrictionSpec spec_;
};

/// The law of a scenario's friction keys, mu = material.mu; `periodic`: the grid wraps.
std::unique_ptr<FrictionLaw> make_friction_law(const FrictionSpec& spec, double mu,
                                               bool periodic = false);

}  // namespace fretbem
