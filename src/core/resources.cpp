#include "fretbem/core/resources.hpp"

#if __has_include(<malloc.h>)
#include <malloc.h>
#endif
#include <sched.h>
#include <unistd.h>

#include <algorithm>
#include <charconv>
#include <cstdlib>
#include <fstream>
#include <thread>

namespace fretbem {

namespace {

std::optional<double> read_positive(const std::string& text) {
  double v = 0;
  const auto r = std::from_chars(text.data(), text.data() + text.size(), v);
  if (r.ec != std::errc() || !(v > 0)) return std::nullopt;
  return v;
}

std::string first_line(const std::string& file) {
  std::ifstream in(file);
  std::string line;
  std::getline(in, line);
  return line;
}

// The cgroup v2 path of this process ("0::/user.slice/..." in /proc/self/cgroup); empty when
// the process sits at the root or the file is missing (containers usually see "/").
std::string own_cgroup_v2_path() {
  std::ifstream in("/proc/self/cgroup");
  for (std::string line; std::getline(in, line);)
    if (line.rfind("0::", 0) == 0) return line.substr(3);
  return "";
}

}  // namespace

std::optional<int> slurm_cpus_per_task() {
  const char* s = std::getenv("SLURM_CPUS_PER_TASK");
  if (!s) return std::nullopt;
  int v = 0;
  const std::string t(s);
  const auto r = std::from_chars(t.data(), t.data() + t.size(), v);
  if (r.ec != std::errc() || r.ptr != t.data() + t.size() || v < 1) return std::nullopt;
  return v;
}

int usable_cpus() {
  int n = 0;
  cpu_set_t set;
  CPU_ZERO(&set);
  if (sched_getaffinity(0, sizeof set, &set) == 0) n = CPU_COUNT(&set);
  if (n < 1) n = int(std::thread::hardware_concurrency());
  if (const auto slurm = slurm_cpus_per_task()) n = n > 0 ? std::min(n, *slurm) : *slurm;
  return std::max(1, n);
}

std::optional<double> cgroup_memory_limit(const std::string& root) {
  return cgroup_memory_limit(root, own_cgroup_v2_path());
}

std::optional<double> cgroup_memory_limit(const std::string& root, const std::string& own) {
  // cgroup v2: the smallest memory.max from the own group up to the root. Slurm sets the job's
  // limit on job_N and leaves "max" in the step and task groups below it, where the process is.
  std::optional<double> limit;
  bool any_v2 = false;
  for (std::string path = own;;) {
    while (!path.empty() && path.back() == '/') path.pop_back();
    const std::string v2 = first_line(root + path + "/memory.max");
    any_v2 = any_v2 || !v2.empty();
    if (const auto v = v2 == "max" ? std::nullopt : read_positive(v2))
      limit = limit ? std::min(*limit, *v) : *v;
    if (path.empty()) break;
    const auto slash = path.find_last_of('/');
    path.resize(slash == std::string::npos ? 0 : slash);
  }
  if (any_v2) return limit;
  // cgroup v1: "no limit" reads as a page-rounded 2^63 - 1.
  const auto v1 = read_positive(first_line(root + "/memory/memory.limit_in_bytes"));
  if (v1 && *v1 < 0x1p62) return v1;
  return std::nullopt;
}

double usable_memory_bytes() {
  const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGE_SIZE);
  const double phys = pages > 0 && page > 0 ? double(pages) * double(page) : 0.0;
  const auto limit = cgroup_memory_limit();
  if (!limit) return phys;
  return phys > 0 ? std::min(phys, *limit) : *limit;
}

void keep_freed_memory() {
#if defined(M_MMAP_THRESHOLD) && defined(M_TRIM_THRESHOLD)
  // Fixed thresholds also turn off glibc's dynamic ones; 256 MiB keeps every field of an
  // n = 2048 run on the heap, and trimming only above 512 MiB of free top.
  mallopt(M_MMAP_THRESHOLD, 256 << 20);
  mallopt(M_TRIM_THRESHOLD, 512 << 20);
#endif
}

}  // namespace fretbem
