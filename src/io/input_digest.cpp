#include "fretbem/io/input_digest.hpp"


#include "fretbem/core/errors.hpp"
#include "fretbem/core/fingerprint.hpp"

namespace fretbem {

InputDigest input_digest(const Model& m) {
  Fingerprint path, surface;
  for (const LoadStep& s : m.path.steps) {
    path.add(s.time);
    path.add(s.normal.value);
    path.add(s.target.x());
    path.add(s.target.y());
    path.add_word(std::uint64_t(s.cycle) << 8 | std::uint64_t(s.normal.force_control) << 3 |
                  std::uint64_t(s.control) << 2 | std::uint64_t(s.relative) << 1 |
                  std::uint64_t(s.turning));
  }
  surface.add_word(std::uint64_t(m.surface0.rows()) << 32 | std::uint64_t(m.surface0.cols()));
  for (double z : m.surface0.reshaped()) surface.add(z);
  return {path.hex(), surface.hex()};
}

void check_input_digest(const InputDigest& stored, const Model& m) {
  const InputDigest now = input_digest(m);
  const std::string why =
      " differs from the one this run started with (an input file edited since, or another "
      "fretbem version that builds it otherwise); restore it, or start a new run; refusing to "
      "resume";
  const Scenario& sc = m.scenario;
  if (now.path != stored.path)
    throw InputError(sc.load.path == PathType::table
                         ? "load.table = " + sc.load.table.string() + ": the load path" + why
                         : "the load path of [load]" + why);
  if (now.surface != stored.surface)
    throw InputError(sc.surface.type == SurfaceType::file
                         ? "surface.file = " + sc.surface.file.string() + ": the surface" + why
                         : "the initial surface of [surface]" + why);
}

}  // namespace fretbem
