// InterfaceState: the per-node memory of the interface, carried from load step to load step.
#pragma once

#include <Eigen/Core>
#include <cstdint>

#include "fretbem/contact/tangential_operator.hpp"

namespace fretbem {

/// Contact state of a node (the `state` output field).
enum class NodeState : std::uint8_t { open = 0, stick = 1, slip = 2 };
using StateField = Eigen::Array<std::uint8_t, Eigen::Dynamic, Eigen::Dynamic>;

struct InterfaceState {
  Field pressure;             ///< p (Pa)
  VecField traction;          ///< tau (Pa), in the tangential operator's components
  VecField displacement;      ///< tangential surface displacement C tau (m), same components
  StateField state;           ///< open / stick / slip
  VecField slip;              ///< accumulated slip vector sum s (m), operator components
  Field slip_path;            ///< accumulated slip path length sum |s| (m)
  Field dissipation;          ///< dissipated energy density sum tau . s (J/m^2)
  Field wear;                 ///< worn depth (m)
  Vec2 shift{0.0, 0.0};       ///< rigid tangential shift U of the indenter (m), global x-y
  double normal_force = 0.0;  ///< F_z (N)
  double indentation = 0.0;   ///< delta (m)

  /// All fields zero on the grid, with the operator's number of components.
  static InterfaceState zeros(const TangentialOperator& op);
  /// Classifies nodes: open where p = 0, slip where |tau| >= mu p (1 - eps), stick otherwise.
  /// eps is the stick tolerance (documented in README: slip nodes sit on the bound because the
  /// solver projects them there; eps only guards round-off).
  void classify(const Field& bound, double eps);
};

}  // namespace fretbem
