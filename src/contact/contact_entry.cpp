#include "fretbem/contact/contact_entry.hpp"

#include <algorithm>

namespace fretbem {

bool entry_fraction(const Field& gap0, const Field& p0, const Field& p1, double normal_self,
                    Field& theta) {
  theta = Field::Zero(p1.rows(), p1.cols());
  bool any = false;
  for (Eigen::Index k = 0; k < p1.size(); ++k) {
    if (!(p0(k) == 0.0 && p1(k) > 0.0)) continue;
    const double g0 = std::max(gap0(k), 0.0);  // a touching node (g0 = 0) entered at the start
    theta(k) = g0 / (g0 + normal_self * p1(k));
    any = any || theta(k) > 0.0;
  }
  return any;
}

void loss_fraction(const Field& gap1, const Field& p0, const Field& p1, double normal_self,
                   Field& theta) {
  theta = Field::Ones(p1.rows(), p1.cols());
  for (Eigen::Index k = 0; k < p1.size(); ++k) {
    if (!(p0(k) > 0.0 && p1(k) == 0.0)) continue;
    const double c = normal_self * p0(k);
    theta(k) = c / (c + std::max(gap1(k), 0.0));  // an open node at zero gap opened at the end
  }
}

void entry_reference(const Field& theta, const Eigen::VectorXd& dU, const VecField& u,
                     const VecField& tau, double tangential_self, const VecField& u0,
                     VecField& u0e) {
  u0e = u0;
  for (Eigen::Index k = 0; k < theta.size(); ++k) {
    if (!(theta(k) > 0.0)) continue;
    for (std::size_t c = 0; c < u0.size(); ++c) {
      const double s = dU(c) - (u[c](k) - u0[c](k));
      u0e[c](k) -= theta(k) * (s + tangential_self * tau[c](k));
    }
  }
}

}  // namespace fretbem
