// Contact entry and loss within a load step: a node whose gap closes part-way through the step
// carries traction only from the moment it touches, and one whose gap opens only until it
// opens. The tangential increment solves the step at its end state, which glues an entering
// node over the whole step; its relative tangential motion before it touched is free motion,
// not slip, and not stored elastically either. Left in, it is a traction error of the order of
// the step at every node the growing contact takes in, locked in while the node sticks: the
// loop under a varying normal load is then first order in the step. A node leaving contact
// slips with its falling bound only until it opens; its motion after that is free motion too,
// which the step's work must not book (step_work.hpp; docs/algorithms.md, "A moving bound
// within a step").
#pragma once

#include <Eigen/Core>

#include "fretbem/contact/interface_state.hpp"

namespace fretbem {

/// Fraction theta in (0, 1) of the step at which each node entering contact in it touched (0
/// at every other node): the contact function, -gap / c_nn while open and p in contact,
/// interpolated linearly between the step's ends, theta = g0 / (g0 + c_nn p1).
/// gap0: the normal gap at the step's start (m); p0, p1: the pressure at its start and end
/// (Pa); normal_self: c_nn, a node's normal displacement per unit pressure on its own cell
/// (m/Pa). Returns whether any node entered.
bool entry_fraction(const Field& gap0, const Field& p0, const Field& p1, double normal_self,
                    Field& theta);

/// Fraction theta in (0, 1] of the step at which each node losing contact in it opened (1 at
/// every other node): the same contact function between p0 > 0 and -gap1 / c_nn,
/// theta = c_nn p0 / (c_nn p0 + gap1). gap1: the normal gap at the step's end (m).
void loss_fraction(const Field& gap1, const Field& p0, const Field& p1, double normal_self,
                   Field& theta);

/// The tangential reference of the step with the entering nodes' free motion before they
/// touched taken out: u0e = u0 - theta s_free, s_free = s + c_tt tau the relative slip the
/// node would have made over the step carrying no traction (s = dU - (u - u0) of a solved
/// increment with traction tau and displacement u, c_tt = tangential_self in m/Pa). Solving the
/// increment again against u0e sticks the node to where it touched.
void entry_reference(const Field& theta, const Eigen::VectorXd& dU, const VecField& u,
                     const VecField& tau, double tangential_self, const VecField& u0,
                     VecField& u0e);

}  // namespace fretbem
