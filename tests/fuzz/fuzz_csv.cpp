// libFuzzer target: the CSV reader (core/csv_reader) and the load-table reader on top of it.
#include <cstddef>
#include <cstdint>

#include "fretbem/core/csv_reader.hpp"
#include "fretbem/core/errors.hpp"
#include "fretbem/history/load_path.hpp"
#include "fuzz_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto path = fretbem_fuzz::write_input("table.csv", data, size);
  try {
    fretbem::csv::read_table(path);
  } catch (const fretbem::InputError&) {
  }
  try {
    fretbem::LoadSpec spec;
    spec.normal_force = 10.0;
    fretbem::read_load_table(path, spec, 0.5);
  } catch (const fretbem::InputError&) {
  }
  return 0;
}
