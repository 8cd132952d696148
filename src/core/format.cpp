#include "fretbem/core/format.hpp"

#include <charconv>
#include <cmath>
#include <cstdio>

namespace fretbem {

std::string format_number(double v) {
  if (std::isnan(v)) return "nan";  // to_chars would give "-nan" for a negative NaN
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

double snap_count(double N) {
  const double r = std::nearbyint(N);
  if (!std::isfinite(N) || std::abs(r) >= 0x1p53) return N;
  const double ulp = std::nextafter(std::abs(N), INFINITY) - std::abs(N);
  return std::abs(N - r) <= kCountUlps * ulp ? r : N;
}

std::string format_count(double N) {
  const double r = snap_count(N);
  if (r != std::nearbyint(r) || std::abs(r) >= 0x1p53) return format_number(N);
  char buf[32];
  const auto end = std::to_chars(buf, buf + sizeof buf, static_cast<long long>(r)).ptr;
  return std::string(buf, end);
}

std::string format_printf(const char* fmt, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, fmt, v);
  return buf;
}

}  // namespace fretbem
