// libFuzzer target: study files of `fretbem sweep` (study/sweep_spec): [study], [vary], [fixed]
// sections, value lists and ranges, member expansion and each member's scenario check. The
// input is the study file; its `scenario = base.ini` finds a small valid base scenario.
#include <cstddef>
#include <cstdint>
#include <fstream>

#include "fretbem/core/errors.hpp"
#include "fretbem/study/sweep_spec.hpp"
#include "fuzz_input.hpp"

namespace {

const char* kBase =
    "[material]\nE = 210e9\nnu = 0.3\nmu = 0.5\n[grid]\nn = 16\nlength = 2.8e-4\n"
    "[surface]\ntype = sphere\nradius = 0.01\n[load]\nnormal_force = 10\npath = sine\n"
    "amplitude = 0.5\ncycles = 1\nsteps_per_cycle = 8\n";

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const bool base_written = [] {
    std::ofstream(fretbem_fuzz::scratch_dir() / "base.ini") << kBase;
    return true;
  }();
  (void)base_written;
  const auto path = fretbem_fuzz::write_input("study.ini", data, size);
  try {
    fretbem::load_sweep_spec(path, {}, fretbem_fuzz::scratch_dir() / "out");
  } catch (const fretbem::InputError&) {
  }
  return 0;
}
