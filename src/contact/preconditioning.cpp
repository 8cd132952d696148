#include "fretbem/contact/preconditioning.hpp"

#include <algorithm>
#include <vector>

#include "slab_preconditioning.hpp"

namespace fretbem {

std::int64_t largest_contact_patch(const Field& bound) {
  const Eigen::Index nx = bound.rows(), ny = bound.cols();
  std::vector<std::uint8_t> seen(std::size_t(bound.size()), 0);
  std::vector<Eigen::Index> stack;
  std::int64_t largest = 0;
  for (Eigen::Index k0 = 0; k0 < bound.size(); ++k0) {
    if (!(bound(k0) > 0.0) || seen[k0]) continue;
    std::int64_t size = 0;
    stack.assign(1, k0), seen[k0] = 1;
    while (!stack.empty()) {  // flood fill over the 4-neighbours
      const Eigen::Index k = stack.back(), i = k % nx, j = k / nx;
      stack.pop_back(), ++size;
      const Eigen::Index next[4] = {i > 0 ? k - 1 : -1, i + 1 < nx ? k + 1 : -1,
                                    j > 0 ? k - nx : -1, j + 1 < ny ? k + nx : -1};
      for (const Eigen::Index m : next)
        if (m >= 0 && bound(m) > 0.0 && !seen[m]) seen[m] = 1, stack.push_back(m);
    }
    largest = std::max(largest, size);
  }
  return largest;
}

bool PreconditionDecision::for_grid(const Grid& grid) const {
  if (mode_ != Precondition::automatic) return mode_ == Precondition::on;
  return std::int64_t(grid.size()) >= kGridCells;
}

bool PreconditionDecision::for_set(const Field& set) const {
  if (mode_ != Precondition::automatic) return mode_ == Precondition::on;
  return largest_contact_patch(set) >= kPatchNodes;
}

// Patches cross slab boundaries, so the flood fill needs the whole set: slabs are consecutive
// rows, and their concatenation in rank order is the (nx, ny) field.
bool for_distributed_set(const PreconditionDecision& decision, const Field& slab, const Grid& grid,
                         const Communicator& comm) {
  if (decision.mode() != Precondition::automatic) return decision.mode() == Precondition::on;
  constexpr auto kPatchNodes = PreconditionDecision::kPatchNodes;
  if (comm.sum(double((slab > 0.0).count())) < double(kPatchNodes)) return false;
  const std::vector<double> all = comm.gather({slab.data(), std::size_t(slab.size())}, 0);
  double on = 0.0;
  if (comm.rank() == 0)
    on = decision.for_set(Eigen::Map<const Field>(all.data(), grid.nx, grid.ny)) ? 1.0 : 0.0;
  comm.broadcast({&on, 1}, 0);
  return on > 0.0;
}

}  // namespace fretbem
