// InterfaceState: the per-node memory of the interface, carried from load step to load step.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <span>

#include "fretbem/contact/tangential_operator.hpp"

namespace fretbem {

/// Contact state of a node. The `state` output field writes open 0, stick 1, slip 2, with
/// stuck_at_bound counted as stick (it did not slip).
enum class NodeState : std::uint8_t { open = 0, stick = 1, slip = 2, stuck_at_bound = 3 };
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
  /// Classifies nodes by the state of the step, not by its history: open where
  /// the bound g = 0; slip where the node is on its bound (|tau| >= g (1 - eps), eps the solver
  /// tolerance guarding round-off) and its slip this step |s| exceeds slip_threshold (m);
  /// stuck_at_bound where on the bound but not slipping; stick inside the bound.
  /// step_slip: |s| per node (m); an empty field means no slip this step.
  void classify(const Field& bound, double eps, const Field& step_slip, double slip_threshold);
  /// The same on the listed nodes only (indices into the fields), for a bound whose contact
  /// nodes are these and whose other nodes are open already (a contact that does not change).
  void classify(const Field& bound, double eps, const Field& step_slip, double slip_threshold,
                std::span<const Eigen::Index> nodes);
};

}  // namespace fretbem
