#include "fretbem/contact/preconditioning.hpp"

#include <algorithm>

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

}  // namespace fretbem
