// A load table of two periods in which F_z and F_x vary together (time in s, forces in N):
// F_z 10, 13, 10, 7 N and F_x = 2 sin(2 pi t) N sampled 8 times a period, exact zeros at
// the half periods. The bound mu p moves every step, and nodes stop on it without slipping.
#pragma once

#include <filesystem>
#include <fstream>

namespace fretbem_test {

inline void write_varying_normal_table(const std::filesystem::path& file) {
  std::ofstream t(file);
  t << "time,Fz,Fx\n";
  const double fx[] = {0, 1.41421, 2, 1.41421, 0, -1.41421, -2, -1.41421};
  for (int i = 0; i <= 16; ++i)
    t << i / 8.0 << "," << (i % 2 ? (i % 4 == 1 ? 13 : 7) : 10) << "," << fx[i % 8] << "\n";
}

}  // namespace fretbem_test
