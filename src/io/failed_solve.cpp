#include "fretbem/io/failed_solve.hpp"

#include <sstream>

#include "fretbem/core/format.hpp"
#include "fretbem/io/hdf5_writer.hpp"

namespace fretbem {

std::filesystem::path write_failed_solve(const std::filesystem::path& dir, const FailedSolve& f) {
  io::Hdf5Writer h5(dir, "failed_solve.h5");
  std::ostringstream in;
  in << "solve = " << f.solve << "\ncontrol = " << f.control << "\ntarget =";
  for (Eigen::Index c = 0; c < f.target.size(); ++c) in << ' ' << format_number(f.target(c));
  in << "\ntarget_units = "
     << (f.solve == "normal" ? (f.control == "force" ? "N" : "m")
                             : (f.control == "force" ? "N" : "m (shift increment)"))
     << "\ncomponents = " << f.tau0.size() << "\ndirection = " << format_number(f.direction.x())
     << ' ' << format_number(f.direction.y()) << '\n';
  h5.write_text("/inputs", in.str());
  if (!f.scenario.empty()) h5.write_text("/scenario", f.scenario);
  if (f.surface.size()) h5.write_field("/surface", f.surface);
  if (f.pressure_start.size()) h5.write_field("/pressure_start", f.pressure_start);
  if (f.bound.size()) h5.write_field("/bound", f.bound);
  for (std::size_t c = 0; c < f.tau0.size(); ++c) {
    h5.write_field("/tau0_" + std::to_string(c), f.tau0[c]);
    if (c < f.u0.size()) h5.write_field("/u0_" + std::to_string(c), f.u0[c]);
  }
  return h5.path();
}

}  // namespace fretbem
