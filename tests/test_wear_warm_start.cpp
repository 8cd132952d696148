// WearWarmStart: the start of a wear-map evaluation's normal solve extrapolated along the
// integrator's path. On a fixed contact set the pressure is affine in the worn depth (C p =
// delta - (z0 - W) on the set), so the identity checked here is that of an affine map: where the
// new worn depth is an affine combination of the path's, the start is the map's value there.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>

#include "fretbem/wear/warm_start.hpp"

using namespace fretbem;

namespace {

constexpr int kN = 16;

// An affine pressure of the worn depth on a fixed contact set (p0 > 0 on it, 0 off it): any
// linear response L W (here a node-wise gain and a neighbour coupling) plus p0.
Field affine_pressure(const Field& W, const Field& p0) {
  Field shifted = W;
  shifted.topRows(kN - 1) = W.bottomRows(kN - 1);
  const Field on = (p0 > 0.0).cast<double>();
  return on * (p0 + 3e9 * W - 1e9 * shifted);
}

// Worn depths of `scale` (m): at 1e-2 the response moves the pressure by up to ~1e8 Pa.
Field random_field(unsigned seed, double scale = 1e-2) {
  std::srand(seed);
  return Field::Random(kN, kN) * scale;
}

Field contact_pressure() {
  Field p0 = Field::Random(kN, kN).abs() * 1e8 + 5e8;
  p0.leftCols(3) = 0.0;  // out of contact
  return p0;
}

}  // namespace

TEST(WearWarmStart, AffineCombinationOfThePathIsExact) {
  const Field p0 = contact_pressure();
  const Field W0 = random_field(1), W1 = random_field(2), W2 = random_field(3);
  WearWarmStart w;
  for (const Field* W : {&W0, &W1, &W2}) w.remember(*W, affine_pressure(*W, p0));
  // A stage predictor's kind of combination: beyond the last state, off the secant line.
  const Field W = W2 + 0.8 * (W2 - W1) - 0.35 * (W1 - W0);
  const Field start = w.start_for(W, serial_communicator());
  const Field exact = affine_pressure(W, p0);
  const double err = (start - exact).abs().maxCoeff() / exact.abs().maxCoeff();
  std::printf("[ warm start ] affine path: max |start - p(W)| / max p = %.3g\n", err);
  EXPECT_LT(err, 1e-12);
  // The last pressure alone is off by the whole step.
  EXPECT_GT((w.pressure - exact).abs().maxCoeff() / exact.abs().maxCoeff(), 1e-3);
}

TEST(WearWarmStart, RepeatedStateAndShortPathStartFromTheLastPressure) {
  const Field p0 = contact_pressure();
  const Field W0 = random_field(4), W1 = random_field(5);
  WearWarmStart w;
  EXPECT_EQ(w.start_for(W0, serial_communicator()).size(), 0);  // cold
  w.remember(W0, affine_pressure(W0, p0));
  EXPECT_TRUE((w.start_for(W1, serial_communicator()) == w.pressure).all());
  w.remember(W1, affine_pressure(W1, p0));
  EXPECT_TRUE((w.start_for(W1, serial_communicator()) == w.pressure).all());
  // Far beyond the path (100 secant lengths): the last pressure, not a wild extrapolation.
  EXPECT_TRUE((w.start_for(W1 + 100.0 * (W1 - W0), serial_communicator()) == w.pressure).all());
}

TEST(WearWarmStart, StartKeepsTheLastContactSetAndNoTension) {
  const Field p0 = contact_pressure();
  const Field W0 = random_field(6, 0.1), W1 = random_field(7, 0.1);
  WearWarmStart w;
  w.remember(W0, affine_pressure(W0, p0));
  w.remember(W1, affine_pressure(W1, p0));
  // Three secant lengths on: some pressures of the affine map turn negative.
  const Field W = W1 + 3.0 * (W1 - W0);
  ASSERT_LT(affine_pressure(W, p0).minCoeff(), 0.0);
  const Field start = w.start_for(W, serial_communicator());
  EXPECT_GE(start.minCoeff(), 0.0);
  EXPECT_TRUE(((w.pressure > 0.0) || (start == 0.0)).all());
  EXPECT_TRUE((start.leftCols(3) == 0.0).all());
}

TEST(WearWarmStart, PathKeepsTheLatestEvaluations) {
  WearWarmStart w;
  for (int k = 0; k < WearWarmStart::kDepth + 2; ++k)
    w.remember(Field::Constant(2, 2, k), Field::Constant(2, 2, 10.0 * k));
  ASSERT_EQ(int(w.worn_path.size()), WearWarmStart::kDepth);
  EXPECT_EQ(w.worn_path.front()(0, 0), 2.0);
  EXPECT_EQ(w.worn_path.back()(0, 0), WearWarmStart::kDepth + 1.0);
  EXPECT_EQ(w.pressure(0, 0), 10.0 * (WearWarmStart::kDepth + 1));
}
