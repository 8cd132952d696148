#include "fretbem/history/load_path.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <numbers>
#include <sstream>

#include "fretbem/core/errors.hpp"

namespace fretbem {

namespace {

NormalLoad constant_normal(const LoadSpec& spec) {
  if (spec.indentation) return {false, *spec.indentation};
  return {true, spec.normal_force.value_or(0.0)};
}

Vec2 direction_of(const LoadSpec& spec) {
  const double a = spec.direction * std::numbers::pi / 180.0;
  return {std::cos(a), std::sin(a)};
}

double amplitude_of(const LoadSpec& spec) {
  return spec.control == Control::force ? spec.amplitude : spec.displacement_amplitude;
}

// Times of a sine path: steps_per_cycle equal steps per period plus every quarter period the
// grid misses, so each turning point (and zero crossing) is hit exactly.
std::vector<double> sine_times(int cycles, int spc) {
  std::map<long long, double> t;  // keyed on a fine rational grid to merge duplicates
  const long long q = 4LL * spc;
  for (long long k = 0; k <= (long long)cycles * spc; ++k) t[k * 4] = double(k) / spc;
  for (long long k = 0; k <= 4LL * cycles; ++k) t[k * spc] = double(k) / 4.0;
  std::vector<double> out;
  for (auto& [key, v] : t) out.push_back(double(key) / q);
  return out;
}

// Peak memory per generated load step: 2e6 sine steps made `fretbem check` peak at 333 MB
// (/usr/bin/time), about 160 bytes a step; 200 leaves a margin.
constexpr double kBytesPerStep = 200.0;

// Refuses a ramp or sine path whose steps would not fit in half the physical memory (the
// other half is the grid's), before anything is allocated: load.cycles = 1e8 grew `check`
// past 8 GB, load.steps = 2^30 ended in bad_alloc.
void check_step_count(const LoadSpec& spec) {
  const bool sine = spec.path == PathType::sine;
  const double steps = sine ? (double(spec.cycles) * spec.steps_per_cycle + 4.0 * spec.cycles + 1)
                            : double(spec.steps) + 1;
  const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGE_SIZE);
  if (pages <= 0 || page <= 0) return;  // unknown: let the allocator decide
  const double limit = 0.5 * double(pages) * double(page) / kBytesPerStep;
  if (steps <= limit) return;
  std::ostringstream msg;
  msg << (sine ? "load.cycles x load.steps_per_cycle" : "load.steps") << ": "
      << static_cast<long long>(steps) << " load steps would need "
      << steps * kBytesPerStep / (1 << 30) << " GiB of memory; at most "
      << static_cast<long long>(limit) << " fit on this machine";
  throw InputError(msg.str());
}

}  // namespace

namespace {

// Table times are bounded by 1e100 only: a cycle number past an int's range is clamped to it
// rather than cast (a cast of an out-of-range double is undefined).
int clamp_to_int(double c) {
  constexpr double lo = std::numeric_limits<int>::min(), hi = std::numeric_limits<int>::max();
  return int(std::clamp(c, lo, hi));
}

}  // namespace

int cycle_of_time(double t) {
  return clamp_to_int(std::floor(t + 1e-12));
}

int cycle_containing_end(double t) {
  return clamp_to_int(std::ceil(t - 1e-12) - 1.0);
}

LoadPath make_load_path(const Scenario& sc) {
  const LoadSpec& spec = sc.load;
  if (spec.path == PathType::table) return read_load_table(spec.table, spec, sc.material.mu);
  check_step_count(spec);
  LoadPath path;
  const NormalLoad normal = constant_normal(spec);
  const Vec2 e = direction_of(spec) * amplitude_of(spec);
  path.steps.push_back({0.0, 0, normal, spec.control, Vec2::Zero(), true, false, {}});
  if (spec.path == PathType::ramp) {
    for (int k = 1; k <= spec.steps; ++k) {
      const double t = double(k) / spec.steps;
      path.steps.push_back({t, 0, normal, spec.control, t * e, true, k == spec.steps, {}});
    }
  } else if (spec.path == PathType::sine) {
    const auto times = sine_times(spec.cycles, spec.steps_per_cycle);
    for (std::size_t k = 1; k < times.size(); ++k) {
      const double t = times[k];
      const double phase = std::fmod(t, 1.0);
      const bool turning = std::abs(phase - 0.25) < 1e-12 || std::abs(phase - 0.75) < 1e-12;
      const int cycle = cycle_of_time(t);
      path.steps.push_back({t,
                            cycle,
                            normal,
                            spec.control,
                            std::sin(2 * std::numbers::pi * t) * e,
                            true,
                            turning,
                            {}});
    }
    path.steps.back().turning = true;
  }
  return path;
}

std::optional<Vec2> LoadPath::collinear_direction() const {
  std::optional<Vec2> e;
  for (const auto& s : steps) {
    if (s.target.norm() == 0.0) continue;
    const Vec2 d = s.target.normalized();
    if (!e) {
      e = d;
    } else if (std::abs(e->x() * d.y() - e->y() * d.x()) > 1e-12) {
      return std::nullopt;
    }
  }
  return e ? e : Vec2(1.0, 0.0);
}

bool LoadPath::monotone(std::size_t a, std::size_t b) const {
  if (b <= a || b >= steps.size()) return false;
  const Vec2 total = steps[b].target - steps[a].target;
  for (std::size_t k = a + 1; k <= b; ++k) {
    if (!(steps[k].normal == steps[a].normal) || steps[k].control != steps[a].control) return false;
    const Vec2 d = steps[k].target - steps[k - 1].target;
    if (d.dot(total) < 0.0 ||
        std::abs(d.x() * total.y() - d.y() * total.x()) > 1e-12 * total.norm())
      return false;
  }
  return true;
}

}  // namespace fretbem
