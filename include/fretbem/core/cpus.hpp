// CPUs this process may run on.
#pragma once

namespace fretbem {

/// Number of CPUs in the process's affinity mask (sched_getaffinity): what taskset, cgroups
/// cpusets and batch schedulers allow, which std::thread::hardware_concurrency ignores. At
/// least 1; falls back to hardware_concurrency where the mask cannot be read.
int usable_cpus();

}  // namespace fretbem
