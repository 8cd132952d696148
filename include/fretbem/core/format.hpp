// Number formatting shared by every text output (CSV rows, resolved scenarios, height maps,
// messages): one spelling of each double everywhere.
#pragma once

#include <string>

namespace fretbem {

/// The shortest decimal that reads back to the same double (std::to_chars), so 0.3 prints as
/// "0.3" and every printed value round-trips exactly; NaN prints as "nan" whatever its sign bit.
std::string format_number(double v);

}  // namespace fretbem
