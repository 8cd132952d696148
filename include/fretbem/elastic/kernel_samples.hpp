// The free grid's real-space kernel samples kept between operators of one process: a process
// building many operators of one grid (a study's worker process runs member after member)
// keeps the last grid's samples, the costly part of HalfSpace's construction (about 0.05 s at
// n = 256). The spectra are still transformed per operator, so an operator is bit for bit what
// a fresh process builds.
#pragma once

#include <cstdint>

namespace fretbem {

/// Off by default: a single run would only hold a second copy. Samples above 64 MiB are never
/// kept (the memory guard of a run does not count them).
void keep_kernel_samples(bool on);
/// Free-grid kernel samplings this process has computed (not taken from the kept ones).
std::int64_t kernel_samples_computed();

}  // namespace fretbem
