// What `fretbem check` prints about a prepared model ("fretbem check"): the moduli,
// the Hertz scales of a sphere, the full-sliding shift, steps and memory, and wear's horizon.
// Warnings (ignored keys, the input checks' cautions) go to stderr, as `run` prints them.
#pragma once

#include <string>

#include "fretbem/history/model.hpp"

namespace fretbem {

/// Lines (each ending in '\n') after the "ok" line; a model from prepare_model is enough.
std::string check_report(const Model& model);

}  // namespace fretbem
