// Small helpers shared by the benchmarks in tools/bench (header only: the CMake glob builds one
// executable per .cpp file, so this header is not a benchmark of its own).
#pragma once

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <fstream>
#include <initializer_list>
#include <string>
#include <vector>

namespace bench {

using Clock = std::chrono::steady_clock;

inline double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

inline double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const std::size_t m = v.size() / 2;
  return v.size() % 2 ? v[m] : 0.5 * (v[m - 1] + v[m]);
}

/// Median over `repeats` of the mean time of one call in a batch long enough (>= ~20 ms) that
/// clock resolution and loop overhead do not matter; one warm-up call first.
template <class F>
double time_per_call(F&& f, int repeats) {
  const auto t0 = Clock::now();
  f();
  const double once = std::max(seconds_since(t0), 1e-7);
  const int batch = std::max(1, int(0.02 / once));
  std::vector<double> t;
  for (int r = 0; r < std::max(1, repeats); ++r) {
    const auto t1 = Clock::now();
    for (int b = 0; b < batch; ++b) f();
    t.push_back(seconds_since(t1) / batch);
  }
  return median(t);
}

/// Same with process CPU time (std::clock): on a loaded machine wall time includes the time
/// other processes ran; CPU time counts only ours (all threads, so use it single-threaded).
template <class F>
double cpu_per_call(F&& f, int repeats) {
  const std::clock_t t0 = std::clock();
  f();
  const double once = std::max(double(std::clock() - t0) / CLOCKS_PER_SEC, 1e-6);
  const int batch = std::max(1, int(0.05 / once));
  std::vector<double> t;
  for (int r = 0; r < std::max(1, repeats); ++r) {
    const std::clock_t t1 = std::clock();
    for (int b = 0; b < batch; ++b) f();
    t.push_back(double(std::clock() - t1) / CLOCKS_PER_SEC / batch);
  }
  return median(t);
}

/// The 1-minute load average (from /proc/loadavg), printed with every table: the machine is
/// shared, and absolute times mean little without it.
inline double load_average() {
  std::ifstream in("/proc/loadavg");
  double l = -1.0;
  in >> l;
  return l;
}

/// Prints a benchmark's usage text, on stdout for --help (status 0) and on stderr otherwise, and
/// exits with `status`.
[[noreturn]] inline void exit_with_usage(int status, const char* text) {
  std::fputs(text, status ? stderr : stdout);
  std::exit(status);
}

/// Integer option value in [lo, hi], or exit(2) with the usage.
inline int int_arg(int argc, char** argv, int& i, int lo, int hi, void (*usage)(int)) {
  if (i + 1 >= argc) usage(2);
  char* end = nullptr;
  const long v = std::strtol(argv[++i], &end, 10);
  if (*end != '\0' || v < lo || v > hi) usage(2);
  return int(v);
}

/// One integer option of a benchmark: its flag, where the value goes, and its range.
struct IntOption {
  const char* flag;
  int* value;
  int lo, hi;
};

/// Parses a command line of integer options only; --help/-h exit(0) with the usage, anything
/// else exit(2) with it.
inline void parse_int_options(int argc, char** argv, const std::vector<IntOption>& options,
                              void (*usage)(int)) {
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--help" || a == "-h") usage(0);
    const IntOption* hit = nullptr;
    for (const IntOption& o : options)
      if (a == o.flag) hit = &o;
    if (!hit) usage(2);
    *hit->value = int_arg(argc, argv, i, hit->lo, hit->hi, usage);
  }
}

/// parse_int_options with the options of a benchmark over a range of grids first: --min-n and
/// --max-n (cells a side, 8 to 16384) and --repeats (1 to 1000); then its own `more`.
inline void parse_grid_range(int argc, char** argv, int& min_n, int& max_n, int& repeats,
                             std::initializer_list<IntOption> more, void (*usage)(int)) {
  std::vector<IntOption> options{{"--min-n", &min_n, 8, 1 << 14},
                                 {"--max-n", &max_n, 8, 1 << 14},
                                 {"--repeats", &repeats, 1, 1000}};
  options.insert(options.end(), more);
  parse_int_options(argc, argv, options, usage);
}

}  // namespace bench
