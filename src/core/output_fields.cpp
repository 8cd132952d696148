// The output-field table (README "Outputs"). Contact fields are in global x-y components.
#include "fretbem/core/output_fields.hpp"

namespace fretbem {

const std::vector<OutputField>& output_field_table() {
  static const std::vector<OutputField> table = {
      {"pressure", "Pa", "contact pressure", true},
      {"traction_x", "Pa", "shear traction, x component", true},
      {"traction_y", "Pa", "shear traction, y component", true},
      {"state", "1", "contact state (0 open, 1 stick, 2 slip)", true, true},
      {"slip_x", "m", "accumulated slip, x component", true},
      {"slip_y", "m", "accumulated slip, y component", true},
      {"dissipation", "J m-2", "dissipated energy per unit area, cumulative", true},
      {"wear", "m", "worn depth, cumulative", true},
      {"initial", "m", "indenter height, peaks positive", false, false, true},
      {"final", "m", "indenter height, peaks positive", false, false, true},
      {"final_half_space", "m", "half-space surface height (worn), peaks positive"},
      {"final_worn_depth", "m", "worn depth, both bodies"},
      {"final_worn_depth_indenter", "m", "worn depth of the indenter"},
      {"final_worn_depth_half_space", "m", "worn depth of the half-space"},
      {"worn_depth", "m", "worn depth, both bodies"},
  };
  return table;
}

std::vector<std::string> selectable_field_names() {
  std::vector<std::string> names;
  for (const OutputField& f : output_field_table())
    if (f.selectable) names.push_back(f.name);
  return names;
}

}  // namespace fretbem
