// Test surfaces shared by the solver tests (header only).
#pragma once

#include <cstdint>

#include "fretbem/surface/generate.hpp"

namespace fretbem::test_util {

/// Fourier-filtered rough surface of rms slope 0.1.
inline Field rough_fourier(const Grid& grid, double hurst, std::uint64_t seed) {
  RoughSpec spec;
  spec.hurst = hurst;
  spec.rms_slope = 0.1;
  spec.method = RoughMethod::fourier;
  spec.seed = seed;
  return rough_surface(grid, spec);
}

}  // namespace fretbem::test_util
