// Grid: the square-cell surface mesh on which every field lives.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <cstring>

namespace fretbem {

/// A surface field: one value per cell, shape (nx, ny), index (i, j) with i along x.
/// Storage is Eigen's column-major order, so x is the fastest index in memory.
using Field = Eigen::ArrayXXd;

/// Whether two fields hold the same values bit for bit (a cache keyed on a field is then
/// valid): one memcmp, a fraction of an element-wise comparison's cost on a grid.
inline bool same_bits(const Field& a, const Field& b) {
  return a.rows() == b.rows() && a.cols() == b.cols() &&
         (a.size() == 0 ||
          std::memcmp(a.data(), b.data(), std::size_t(a.size()) * sizeof(double)) == 0);
}

/// Cell-centred grid of nx × ny square cells of side h (m), centred on the origin.
/// Node (i, j) sits at the centre of its cell, x_i = (i + 1/2 - nx/2) h.
struct Grid {
  int nx = 0;
  int ny = 0;
  double h = 0.0;         ///< cell side (m)
  bool periodic = false;  ///< periodic surface instead of the free (zero-padded) boundary

  static Grid square(int n, double length, bool periodic = false) {
    return Grid{n, n, length / n, periodic};
  }
  std::size_t size() const { return static_cast<std::size_t>(nx) * ny; }
  double x(int i) const { return (i + 0.5 - 0.5 * nx) * h; }
  double y(int j) const { return (j + 0.5 - 0.5 * ny) * h; }
  double cell_area() const { return h * h; }
  double length_x() const { return nx * h; }
  double length_y() const { return ny * h; }
  Field zeros() const { return Field::Zero(nx, ny); }
};

}  // namespace fretbem
