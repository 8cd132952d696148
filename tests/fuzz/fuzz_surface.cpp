// libFuzzer target: the height-map readers (surface/formats). The first byte picks the format
// (text, .npy, HDF5, .npz, .x3p) and the layout, so one corpus covers all of them.
#include <cstddef>
#include <cstdint>

#include "fretbem/core/errors.hpp"
#include "fretbem/surface/formats.hpp"
#include "fuzz_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  static const char* names[] = {"z.txt", "z.npy", "z.h5", "z.npz", "z.x3p"};
  const auto path = fretbem_fuzz::write_input(names[data[0] % 5], data + 1, size - 1);
  const auto layout = (data[0] / 5) % 2 ? fretbem::HeightLayout::xy : fretbem::HeightLayout::yx;
  try {
    fretbem::read_height_map(path, "", layout);
  } catch (const fretbem::InputError&) {
  }
  return 0;
}
