// The contact and stick nodes of one tangential increment and Coulomb's law on them: the
// residual, the rigid-shift estimate, the projections onto the discs. Internal to src/contact.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "fretbem/contact/tangential_solver.hpp"
#include "node_vectors.hpp"

namespace fretbem::tangential_detail {

/// |tau| per node.
Field magnitude(const VecField& tau);
/// 1 where a node is in contact and strictly inside its Coulomb disc (free to stick), else 0.
Field free_mask(const Field& g, const Field& mag);
// On a grid distributed over ranks every field below is this rank's slab and every sum, count
// and "anything" is over the whole grid, formed through the communicator `comm`.

/// Total force sum tau h^2 per component (N).
Eigen::VectorXd total_force(const VecField& tau, const Grid& grid, const Communicator& comm);
/// Largest attainable tangential force sum g h^2 (N).
double bound_force(const Field& g, const Grid& grid, const Communicator& comm);
/// dU: imposed (displacement control) or the mean of u - u0 over stick nodes (force control).
Eigen::VectorXd shift_estimate(const TangentialIncrement& inc, const VecField& u, const Field& free,
                               const Communicator& comm);
/// Force control at or past full sliding: |F| >= sum g h^2 (1 - tolerance).
bool past_full_sliding(const TangentialIncrement& inc, const Grid& grid, double tolerance,
                       const Communicator& comm);
/// The same with the full-sliding force sum g h^2 (N) at hand.
bool past_full_sliding(const TangentialIncrement& inc, double bound_force, double tolerance);
/// Projects every node onto its disc |tau| <= g (open nodes to zero); true if anything moved
/// on any rank.
bool project_all(const Field& g, VecField& tau, const Communicator& comm);

/// The slip-node step takes no move |y - tau| below this fraction of g: a turn under 1e-14 rad
/// is round-off (slip_node_step.cpp). It leaves up to this fraction of |s| across a sliding
/// node's traction.
inline constexpr double kTurnRoundoff = 1e-14;

/// Relative resolution of a node's slip: slip within this fraction of |dU| + |u| + |u0| (in
/// quadrature) is no violation of Coulomb's law. It is the turn the slip-node step leaves
/// (kTurnRoundoff) plus the arithmetic's: s = dU - (u - u0) carries eps times those magnitudes
/// per component (measured across the traction on a worn contact, g = mu p <= 0.7 kPa under a
/// fixed indentation, sliding 3.4e6 times |C g|: 2.0 (median) to 4.5 (max) eps |s| over its
/// 392 nodes; worn further, to |C g| = 4e-19 m, the turns left reached 45.2 eps |s|, just past
/// kTurnRoundoff). Counted in full, it held those contacts at residuals of 1.7e-9 and 9.4e-5
/// that neither algorithm nor any sub-step could lower.
inline constexpr double kSlipRoundoff = 2.0 * kTurnRoundoff;

class BoundCache;

/// The contact nodes of one increment (g > 0, fixed while the pressure is) and which of them
/// stick. Every per-iteration pass of the projected solver runs over this list instead of the
/// whole grid: off contact tau = 0 and nothing is read (u there is only refreshed by the exact
/// products).
/// On a distributed grid the lists hold this rank's nodes (slab indices) and the counts are
/// over the whole grid.
struct NodeSets {
  NodeSets(const Field& g, const Communicator& comm);
  /// The contact nodes of a bound already scanned (BoundCache).
  NodeSets(const BoundCache& bound, const Communicator& comm);
  /// Marks the contact nodes strictly inside their disc as stick; returns how many (all ranks).
  std::int64_t classify(const Field& g, const VecField& tau);
  /// Sets nstick from the stick flags (all ranks).
  void count_stick();

  const Communicator* comm;           ///< the reduction layer of the grid
  std::vector<Eigen::Index> contact;  ///< slab index of each contact node
  std::vector<std::uint8_t> stick;    ///< per contact node: 1 stick, 0 slip
  std::int64_t ncontact = 0;          ///< contact nodes on all ranks
  std::int64_t nstick = 0;            ///< stick nodes on all ranks
};

/// Coulomb residual (see TangentialResult::residual) over the contact nodes; classifies the
/// stick set first and returns dU and the squared stick slip sum_S |s|^2 (the CG gradient norm).
double residual(NodeSets& sets, const TangentialIncrement& inc, const VecField& tau,
                const VecField& u, double scale, const Grid& grid, Eigen::VectorXd& dU,
                double& stick_slip2);

/// What an increment needs of its bound g, recomputed only when g changes (compared bit for
/// bit): the contact nodes (g > 0), their count over all ranks, sum g (Pa, all ranks) and the
/// displacement scale |C g| (m, rms over contact). Steps at one normal load keep one bound, and
/// the scan, the sum and the comparison of the whole grid cost ~4 % of a steady n = 256 cycle.
class BoundCache {
 public:
  /// Brings the cache up to g (collective: recomputed on every rank when any rank's g changed).
  const BoundCache& update(TangentialOperator& op, const Field& g);
  const std::vector<Eigen::Index>& contact() const { return contact_; }
  std::int64_t ncontact() const { return ncontact_; }
  double gsum() const { return gsum_; }
  double scale() const { return scale_; }

 private:
  Field g_;
  std::vector<Eigen::Index> contact_;
  std::int64_t ncontact_ = 0;
  double gsum_ = 0.0, scale_ = 1.0;
};

/// Force control with no stick node (the whole contact slides): the dU at which the slip
/// directions of the contact nodes carry the target force F (N),
/// sum_k g_k s_k / |s_k| h^2 = F with s_k = dU - (u_k - u0_k), starting from `x`. dU is then
/// the multiplier of the force constraint, which no stick node's mean can give: with the mean
/// the iterate of the coupled normal ramp (beta/mu = 4, n = 32, 4 sub-steps a row) settled
/// at a Coulomb residual of 3.25e-10 against the tolerance 1e-10, its nodes turned by the
/// slip step towards the mean and back by the force correction. The sum is the gradient of
/// the convex sum_k g_k |dU - (u_k - u0_k)|: Newton with halving on the force mismatch. With
/// one component the map is a step function (a node's slip changes sign, not direction) and
/// `x` is returned.
template <int NC>
Vec<NC> sliding_shift(const NodeSets& sets, const TangentialIncrement& inc, const VecField& u,
                      double cell_area, Vec<NC> x) {
  if constexpr (NC == 1) {
    return x;
  } else {
    const Field& g = *inc.bound;
    const Vec<NC> want = inc.target / cell_area;
    std::array<double, NC + NC * NC + 1> sums;
    auto force = [&](const Vec<NC>& dU, Vec<NC>& F, Mat<NC>& J) {
      F.setZero(), J.setZero();
      double gsum = 0.0;
      for (const Eigen::Index k : sets.contact) {
        const Vec<NC> s = dU - (at<NC>(u, k) - at<NC>(*inc.u0, k));
        const double m = s.norm();
        gsum += g(k);
        if (!(m > 0.0)) continue;
        F += s * (g(k) / m);
        J += (g(k) / m) * (Mat<NC>::Identity() - s * s.transpose() / (m * m));
      }
      Eigen::Map<Vec<NC>>(sums.data()) = F;
      Eigen::Map<Mat<NC>>(sums.data() + NC) = J;
      sums[NC + NC * NC] = gsum;
      sets.comm->sum(sums);
      F = Eigen::Map<Vec<NC>>(sums.data()), J = Eigen::Map<Mat<NC>>(sums.data() + NC);
      return sums[NC + NC * NC];
    };
    Vec<NC> F;
    Mat<NC> J;
    const double tol = 1e-15 * force(x, F, J);
    return monotone_newton<NC>(force, x, want, tol, 100).x;
  }
}

/// dU: imposed (displacement control), or the mean of u - u0 over the stick nodes under force
/// control; with no stick node the sliding_shift from the mean over all contact nodes.
template <int NC>
Vec<NC> mean_shift(const NodeSets& sets, const TangentialIncrement& inc, const VecField& u,
                   double cell_area) {
  if (inc.control == TangentialControl::displacement) return inc.target;
  const bool all = sets.nstick == 0;
  Vec<NC> sum = Vec<NC>::Zero();
  for (std::size_t j = 0; j < sets.contact.size(); ++j) {
    if (!all && !sets.stick[j]) continue;
    const Eigen::Index k = sets.contact[j];
    sum += at<NC>(u, k) - at<NC>(*inc.u0, k);
  }
  sets.comm->sum(std::span<double>(sum.data(), NC));
  const Vec<NC> mean = sum / std::max(1.0, double(all ? sets.ncontact : sets.nstick));
  return all ? sliding_shift<NC>(sets, inc, u, cell_area, mean) : mean;
}

}  // namespace fretbem::tangential_detail
