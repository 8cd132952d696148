// libFuzzer target: the checkpoint reader (io/checkpoint) on arbitrary checkpoint.h5 bytes.
//
// Inputs that start with the HDF5 signature (the seeds are checkpoints) are sealed first: the
// checksum block is put in front of them, as the writer does, so that the mutated HDF5 bytes
// reach the reader without the child-process probe of unsealed files (one fork per input ran
// at ~30 inputs/s). HDF5 1.10.8 itself dies on some such files; run with
// `-fork=1 -ignore_crashes=1` to go on past those, and triage the crashes by their stacks
// (docs/reliability.md, "Fuzzing"). Other inputs test the checksum check and the probe.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>

#include "fretbem/core/errors.hpp"
#include "fretbem/io/checkpoint.hpp"
#include "fuzz_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const char signature[] = "\x89HDF\r\n\x1a\n";
  const bool hdf5 = size >= 8 && std::memcmp(data, signature, 8) == 0;
  if (hdf5) {
    std::string bytes(512, '\0');
    const std::string magic = "fretbem checkpoint sum 1\n";
    bytes.replace(0, magic.size(), magic);
    bytes.append(reinterpret_cast<const char*>(data), size);
    fretbem_fuzz::write_input("checkpoint.h5", reinterpret_cast<const std::uint8_t*>(bytes.data()),
                              bytes.size());
    fretbem::reseal_checkpoint(fretbem_fuzz::scratch_dir() / "checkpoint.h5");
  } else {
    fretbem_fuzz::write_input("checkpoint.h5", data, size);
  }
  try {
    fretbem::load_checkpoint(fretbem_fuzz::scratch_dir());
  } catch (const fretbem::InputError&) {
  }
  return 0;
}
