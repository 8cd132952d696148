// Rows of a run with the cycle predictor against the same run without it: the predictor moves
// only where solves start, so the rows agree to the solver tolerance's level, and the work of
// the rows it has starts for (after the first period) is what it changes. Header-only.
#pragma once

#include <gtest/gtest.h>

#include <vector>

#include "fretbem/history/observables.hpp"

namespace fretbem_test {

/// Convolutions of the rows after t = 1 (the periods the predictor has starts for).
struct LaterConvolutions {
  long predicted = 0;  ///< of the run with the predictor
  long plain = 0;      ///< of the run without it
};

/// Expects rows `a` (predictor) and `b` (none) alike: F_x within 1e-6 of mu F_z of row 1 and the
/// dissipation within 1e-6 of the last row's (solver.tolerance 1e-10, as
/// Predictor.VaryingNormalLoadCostsNoMoreThanWithoutIt); returns their later convolutions.
inline LaterConvolutions expect_rows_alike(const std::vector<fretbem::StepRecord>& a,
                                           const std::vector<fretbem::StepRecord>& b, double mu) {
  LaterConvolutions c;
  EXPECT_EQ(a.size(), b.size());
  if (a.size() != b.size() || a.size() < 2) return c;
  const double Fs = mu * a[1].Fz, E = a.back().dissipation;
  for (std::size_t k = 1; k < a.size(); ++k) {
    EXPECT_NEAR(a[k].Fx, b[k].Fx, 1e-6 * Fs) << k;
    EXPECT_NEAR(a[k].dissipation, b[k].dissipation, 1e-6 * E) << k;
    if (a[k].time > 1.0) c.predicted += a[k].convolutions, c.plain += b[k].convolutions;
  }
  return c;
}

}  // namespace fretbem_test
