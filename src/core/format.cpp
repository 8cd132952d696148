#include "fretbem/core/format.hpp"

#include <charconv>
#include <cmath>

namespace fretbem {

std::string format_number(double v) {
  if (std::isnan(v)) return "nan";  // to_chars would give "-nan" for a negative NaN
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

}  // namespace fretbem
