// WearModel: the local wear law, asked once per load step for the worn-depth increment of every
// node from its pressure, end-of-step traction and slip increment (docs/wear.md; laws
// are small interfaces, one file per law: docs/architecture.md). Nothing else knows which law
// is in use.
#pragma once

#include <memory>

#include "fretbem/contact/step_work.hpp"
#include "fretbem/scenario/scenario.hpp"

namespace fretbem {

class WearModel {
 public:
  virtual ~WearModel() = default;
  /// Worn-depth increment dh (m) per node for one step, from its slip length, the pressure
  /// along the slip and the frictional work, all by the one quadrature of the bound that the
  /// dissipation takes (contact/step_work.hpp).
  virtual Field increment(const StepWork& step) const = 0;
  /// An Archard coefficient k_eq with dh <= k_eq p |s| for this law (Coulomb friction with
  /// coefficient mu): what the explicit integrator's stability bound needs.
  virtual double archard_equivalent(double mu) const = 0;
};

/// Local Archard law dh = k p |s|, p the pressure along the slip (Archard 1953, applied pointwise:
/// e.g. Põdra & Andersson, Wear 207, 1997).
class ArchardWear final : public WearModel {
 public:
  explicit ArchardWear(double k) : k_(k) {}
  Field increment(const StepWork& step) const override;
  double archard_equivalent(double) const override { return k_; }

 private:
  double k_;
};

/// Dissipated-energy law dh = alpha x the frictional work of the step (Fouvry et al., Wear
/// 255, 2003).
class EnergyWear final : public WearModel {
 public:
  explicit EnergyWear(double alpha) : alpha_(alpha) {}
  Field increment(const StepWork& step) const override;
  /// The work at a Coulomb slip node is its bound along the slip times |s|, mu p |s|.
  double archard_equivalent(double mu) const override { return alpha_ * mu; }

 private:
  double alpha_;
};

/// The law of wear.law, or null for wear.law = none (no wear arithmetic at all).
std::unique_ptr<WearModel> make_wear_model(const WearSpec& spec);

}  // namespace fretbem
