// Number formatting shared by every text output (CSV rows, resolved scenarios, height maps,
// messages): one spelling of each double everywhere.
#pragma once

#include <string>

namespace fretbem {

/// The shortest decimal that reads back to the same double (std::to_chars), so 0.3 prints as
/// "0.3" and every printed value round-trips exactly; NaN prints as "nan" whatever its sign bit.
std::string format_number(double v);

/// A cycle count N: integral values print as integers ("3", "1000000", not "1e+06"), also when
/// round-off left them a few ulps off (2.9999999999999996 from summed increments: within
/// kCountUlps ulps of the integer); any other value as format_number.
std::string format_count(double N);
/// The integer a cycle count stands for when it is one (as format_count decides), else N.
double snap_count(double N);
inline constexpr double kCountUlps = 64.0;

/// v through a printf conversion for one double ("%.2g"): report lines with a chosen precision.
std::string format_printf(const char* fmt, double v);

}  // namespace fretbem
