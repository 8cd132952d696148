// libFuzzer target: the checkpoint reader (io/checkpoint) on arbitrary checkpoint.h5 bytes.
#include <cstddef>
#include <cstdint>

#include "fretbem/core/errors.hpp"
#include "fretbem/io/checkpoint.hpp"
#include "fuzz_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  fretbem_fuzz::write_input("checkpoint.h5", data, size);
  try {
    fretbem::load_checkpoint(fretbem_fuzz::scratch_dir());
  } catch (const fretbem::InputError&) {
  }
  return 0;
}
