// Number formatting (core/format.hpp): cycle counts print as integers where they are integral,
// also a few ulps off after summed increments, and every other value exactly as format_number.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "fretbem/core/format.hpp"

using namespace fretbem;

TEST(FormatCount, IntegralCountsPrintAsIntegers) {
  EXPECT_EQ(format_count(0.0), "0");
  EXPECT_EQ(format_count(3.0), "3");
  EXPECT_EQ(format_count(1e6), "1000000");  // %g and to_chars give 1e+06
  EXPECT_EQ(format_count(5e4), "50000");
  EXPECT_EQ(format_count(-2.0), "-2");
  // Round-off of summed increments: 3 - 1 ulp, 0.1 summed ten times (1 - 1 ulp), a count of
  // 1e4 reached by steps of 0.1 (10^5 additions, ~1e-9 off: not round-off any more, kept).
  EXPECT_EQ(format_count(std::nextafter(3.0, 0.0)), "3");
  EXPECT_EQ(format_count(std::nextafter(3.0, 4.0)), "3");
  double s = 0.0;
  for (int k = 0; k < 10; ++k) s += 0.1;
  ASSERT_NE(s, 1.0);
  EXPECT_EQ(format_count(s), "1");
  double N = 0.0;
  for (int k = 0; k < 20; ++k) N += 1.0 / 3.0 + 1.0 / 3.0 + 1.0 / 3.0;
  EXPECT_EQ(format_count(N), "20");
}

TEST(FormatCount, NonIntegralValuesAreUnchanged) {
  for (const double v : {2.5, 113.75, 0.1, 3.0 + 1e-9, 3.0 - 1e-12, 1e4 + 1e-8, 1e-300,
                         std::numeric_limits<double>::infinity(),
                         std::numeric_limits<double>::quiet_NaN(), 0x1p60 + 0x1p8}) {
    EXPECT_EQ(format_count(v), format_number(v)) << v;
    if (!std::isnan(v)) {
      EXPECT_EQ(snap_count(v), v) << v;
    }
  }
  EXPECT_EQ(snap_count(std::nextafter(3.0, 0.0)), 3.0);
}
