// Load tables whose normal load varies: the sampled sine F_z = P (1 + 0.3 sin 2 pi t),
// F_x = 0.5 mu P cos 2 pi t, below a coarse table of 8 rows a period, and a 12-row table.
// A load table of two periods in which F_z and F_x vary together (time in s, forces in N):
// F_z 10, 13, 10, 7 N and F_x = 2 sin(2 pi t) N sampled 8 times a period, exact zeros at
// the half periods. The bound mu p moves every step, and nodes stop on it without slipping.
#pragma once

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>

namespace fretbem_test {

/// F_z = P (1 + 0.3 sin 2 pi t), F_x = 0.5 mu P cos 2 pi t (N) sampled at `rows_per_period`
/// rows a period over `periods` periods, each interval split into `split` equal rows along the
/// straight line between its samples (the same piecewise-linear path in more rows); with a
/// prelude, first a push to F_x = 0.9 mu P and the periodic load one period later.
inline void write_sine_normal_table(const std::filesystem::path& file, int rows_per_period,
                                    double P, double mu, int periods = 3, bool prelude = false,
                                    int split = 1) {
  std::ofstream out(file);
  out << std::setprecision(17) << "time,Fz,Fx\n";
  if (prelude) out << "0," << P << "," << 0.9 * mu * P << "\n";
  auto fz = [&](double t) { return P * (1 + 0.3 * std::sin(2 * M_PI * t)); };
  auto fx = [&](double t) { return 0.5 * mu * P * std::cos(2 * M_PI * t); };
  for (int k = prelude ? 1 : 0; k <= periods * rows_per_period; ++k) {
    const double t = double(k) / rows_per_period, t0 = double(k - 1) / rows_per_period;
    for (int j = k > (prelude ? 1 : 0) ? 1 : split; j <= split; ++j) {
      const double w = double(j) / split;
      if (j == split)
        out << t << "," << fz(t) << "," << fx(t) << "\n";
      else
        out << t0 + w * (t - t0) << "," << (1 - w) * fz(t0) + w * fz(t) << ","
            << (1 - w) * fx(t0) + w * fx(t) << "\n";
    }
  }
}

inline void write_varying_normal_table(const std::filesystem::path& file) {
  std::ofstream t(file);
  t << "time,Fz,Fx\n";
  const double fx[] = {0, 1.41421, 2, 1.41421, 0, -1.41421, -2, -1.41421};
  for (int i = 0; i <= 16; ++i)
    t << i / 8.0 << "," << (i % 2 ? (i % 4 == 1 ? 13 : 7) : 10) << "," << fx[i % 8] << "\n";
}

/// One period of 12 rows (combination sweep seed 50 case 7; N, time in periods): F_z = 2.5088 N,
/// 26 % higher at t = 1/12, 1/6, 7/12, 2/3 and 26 % lower at 1/3, 5/12, 5/6, 11/12, and
/// F_x = 0.3 F_z sin(2 pi t): the wear cost guard's costly-step case.
inline constexpr const char* kTwelveRowVaryingTable =
    "time,Fz,Fx\n0,2.5088,0\n0.0833333,3.1606054,0.4740908\n0.1666667,3.1606054,0.8211494\n"
    "0.25,2.5088,0.75264\n0.3333333,1.8569946,0.4824614\n0.4166667,1.8569946,0.2785492\n"
    "0.5,2.5088,0\n0.5833333,3.1606054,-0.4740908\n0.6666667,3.1606054,-0.8211494\n"
    "0.75,2.5088,-0.75264\n0.8333333,1.8569946,-0.4824614\n0.9166667,1.8569946,-0.2785492\n"
    "1,2.5088,0\n";

}  // namespace fretbem_test
