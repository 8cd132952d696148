// Friction laws: the Coulomb bound g_i = mu_i p_i of every node (docs/architecture.md, "Laws are
// small interfaces"). The stepper asks the law for the bound before each step and keeps it fixed
// within the step, so every increment stays the convex problem of docs/algorithms.md; the law
// may change mu_i between steps from the node's history. Nothing else knows which law is in use.
#pragma once

#include <algorithm>
#include <memory>

#include "fretbem/contact/interface_state.hpp"
#include "fretbem/scenario/scenario.hpp"

namespace fretbem {

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

/// Static/kinetic: mu_s at nodes that did not slip in the last step, mu_k at nodes that did.
class StaticKineticFriction final : public FrictionLaw {
 public:
  StaticKineticFriction(double mu_static, double mu_kinetic) : ms_(mu_static), mk_(mu_kinetic) {}
  void bound(const InterfaceState& state, Field& g) const override;
  bool evolves() const override { return true; }
  double min_mu() const override { return std::min(ms_, mk_); }

 private:
  double ms_, mk_;
};

/// Running-in: mu = mu_0 + (mu_final - mu_0) (1 - exp(-X / scale)) per node, X its accumulated
/// dissipated energy density or slip path (a saturating law; Fouvry et al. report mu rising
/// from ~0.2 to ~0.8 over the first hundreds to thousands of fretting cycles).
class EvolvingFriction final : public FrictionLaw {
 public:
  EvolvingFriction(double mu0, const FrictionSpec& spec) : mu0_(mu0), spec_(spec) {}
  void bound(const InterfaceState& state, Field& g) const override;
  bool evolves() const override { return true; }
  double min_mu() const override { return std::min(mu0_, spec_.mu_final); }

 private:
  double mu0_;
  FrictionSpec spec_;
};

/// The law of a scenario's friction keys, mu = material.mu.
std::unique_ptr<FrictionLaw> make_friction_law(const FrictionSpec& spec, double mu);

}  // namespace fretbem
