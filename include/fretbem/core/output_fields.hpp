// The output-field table: every field a run can save (output.fields) and every height map a
// wear run writes, with its unit (UDUNITS spelling, the result.h5 `units` attribute), long
// name, and how it is stored. The scenario reader's field names and result.h5's metadata come
// from it; tools/plot_fields.py is checked against it (tests/plot_tools_test.py).
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace fretbem {

struct OutputField {
  std::string name;       ///< dataset name in result.h5 (and the output.fields spelling)
  std::string units;      ///< "Pa", "m", "J m-2", "1"
  std::string long_name;  ///< what the values are
  /// Per-step contact field a scenario selects with output.fields (else a wear run's map).
  bool selectable = false;
  bool flag = false;   ///< integer flags (state); see kStateMeanings
  bool dense = false;  ///< a height map: a value in every cell, stored uncompressed
};

/// Every field, the selectable ones first in the order output.fields lists them.
const std::vector<OutputField>& output_field_table();
/// The names output.fields accepts, in the table's order.
std::vector<std::string> selectable_field_names();

}  // namespace fretbem
