// libFuzzer target: the height-map readers (surface/formats). The first byte picks the format
// (text, .npy, HDF5) so one corpus covers all three.
#include <cstddef>
#include <cstdint>

#include "fretbem/core/errors.hpp"
#include "fretbem/surface/formats.hpp"
#include "fuzz_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  static const char* names[] = {"z.txt", "z.npy", "z.h5"};
  const auto path = fretbem_fuzz::write_input(names[data[0] % 3], data + 1, size - 1);
  try {
    fretbem::load_height_map(path);
  } catch (const fretbem::InputError&) {
  }
  return 0;
}
