// The half-space kernels one entry at a time: the real-space cell influence coefficients of
// the free grid at one offset, and the periodic grid's spectrum at one wave number. The
// serial engine and the distributed one (mpi_engine.cpp) fill their own layouts from these,
// so that both transform the same numbers. Internal to src/elastic.
#pragma once

#include "fretbem/elastic/grid.hpp"
#include "fretbem/elastic/material.hpp"

namespace fretbem::kernel_values {

/// Which kernels a HalfSpace needs and the constants they are built from.
struct Constants {
  double h = 0.0;        ///< cell side (m)
  double cz = 0.0;       ///< 1 / (pi E*) (1/Pa)
  double ca = 0.0;       ///< Cerruti a (1/Pa)
  double cb = 0.0;       ///< Cerruti b (1/Pa)
  double es = 0.0;       ///< E* (Pa)
  double cross = 0.0;    ///< cross compliance c (1/Pa); 0: no cross kernels
  bool cerruti = false;  ///< the xx, yy, xy kernels are needed
  double Lx = 0.0, Ly = 0.0;
  Constants(const Grid& grid, const Material& m, bool cerruti_kernels, double cross_compliance);
};

/// One entry of each kernel (z: m/Pa; xx, yy, xy: m/Pa; zx, zy: m/Pa), 0 when not needed.
struct Sample {
  double z = 0, xx = 0, yy = 0, xy = 0, zx = 0, zy = 0;
};

/// Free grid: the cell influence coefficients at the offset (dx h, dy h) (love.hpp).
Sample free_at(const Constants& c, int dx, int dy);

/// Periodic grid: the kernel spectra (not yet divided by the transform size) at the mode
/// (m0, m1) of an n0 x n1 transform (m0 along y, m1 along x, m1 <= n1 / 2): the alias sum
/// of the continuous symbols times the cell's form factor; zx, zy hold the imaginary parts.
Sample periodic_at(const Constants& c, int m0, int m1, int n0, int n1);

}  // namespace fretbem::kernel_values
