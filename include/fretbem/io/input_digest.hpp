// Fingerprints of what a run read from its inputs (the load path built from load.table or the
// path keys, the initial surface from surface.file or its generator), kept in checkpoints so
// that a resume refuses an input edited since the run started, or a fretbem that builds them
// otherwise, instead of continuing on a different history (an edited load table was
// followed silently from the resumed step on).
#pragma once

#include <string>

#include "fretbem/history/model.hpp"

namespace fretbem {

struct InputDigest {
  std::string path;     ///< 16 hex digits: FNV-1a over every load step's values
  std::string surface;  ///< 16 hex digits: FNV-1a over the initial surface's shape and heights
  bool operator==(const InputDigest&) const = default;
};

InputDigest input_digest(const Model& model);

/// Refuses (InputError naming the scenario key and file) a model whose digest is not the one
/// stored with its checkpoint.
void check_input_digest(const InputDigest& stored, const Model& model);

}  // namespace fretbem
