// libFuzzer target: the scenario parser (INI text, keys, values, cross-key rules). Any input
// must parse or throw InputError; anything else (crash, other exception, sanitizer report) is
// a finding.
#include <cstddef>
#include <cstdint>
#include <string>

#include "fretbem/core/errors.hpp"
#include "fretbem/scenario/scenario.hpp"
#include "fuzz_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    fretbem::parse_scenario(text, "fuzz.ini", fretbem_fuzz::scratch_dir());
  } catch (const fretbem::InputError&) {
  }
  return 0;
}
