// Error types: every failure a user can cause or meet has a one-line message.
#pragma once

#include <stdexcept>
#include <string>

namespace fretbem {

/// Bad input: a scenario key, a value, a file. The message names it.
struct InputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// A solver that did not converge, or met an impossible load (e.g. F_t >= mu F_z).
struct SolverError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

}  // namespace fretbem
