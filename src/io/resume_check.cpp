#include "fretbem/io/resume_check.hpp"

#include <chrono>
#include <cmath>
#include <fstream>
#include <random>
#include <vector>

#include "fretbem/core/errors.hpp"
#include "fretbem/core/format.hpp"
#include "fretbem/core/text_file.hpp"
#include "fretbem/io/replaced_results.hpp"
#include "fretbem/io/run_files.hpp"

namespace fretbem {

namespace fs = std::filesystem;

namespace {

// The files a run writes; any of them marks a directory as holding a run's results.
const char* const kRunFiles[] = {"timeseries.csv", "cycles.csv", "result.h5", "checkpoint.h5"};

[[noreturn]] void refuse(const fs::path& file, const std::string& what) {
  throw InputError(file.string() + ": " + what + "; refusing to resume");
}

bool all_finite(const Field& f) {
  return f.allFinite();
}

void check_field(const fs::path& file, const std::string& name, const Field& f, const Grid& g,
                 bool nonnegative = false) {
  if (f.rows() != g.nx || f.cols() != g.ny)
    refuse(file, name + " is " + std::to_string(f.rows()) + " x " + std::to_string(f.cols()) +
                     " but the scenario's grid is " + std::to_string(g.nx) + " x " +
                     std::to_string(g.ny));
  if (!all_finite(f)) refuse(file, name + " holds non-finite values");
  if (nonnegative && (f < 0).any()) refuse(file, name + " holds negative values");
}

void check_scalar(const fs::path& file, const std::string& name, double v) {
  if (!std::isfinite(v)) refuse(file, name + " = " + std::to_string(v) + " is not finite");
}

void check_wear(const fs::path& file, const WearCheckpoint& w, const Model& m) {
  check_field(file, "wear_worn", w.worn, m.scenario.grid);
  check_scalar(file, "wear N", w.N);
  if (w.N < 0 || w.N > m.scenario.wear.cycles)
    refuse(file, "wear N = " + format_count(w.N) + " outside [0, wear.cycles]");
  check_scalar(file, "wear h_next", w.h_next);
  if (std::isnan(w.h_max) || w.h_max <= 0 || w.h_next < 0)
    refuse(file, "wear step sizes out of range");
  check_scalar(file, "wear simulated cycles", w.counters.simulated);
  check_scalar(file, "wear_atol", w.atol);
  if (w.atol < 0.0) refuse(file, "wear_atol = " + format_number(w.atol) + " is negative");
}

}  // namespace

std::string new_run_id() {
  std::random_device rd;
  const auto t = std::chrono::system_clock::now().time_since_epoch().count();
  const unsigned long long id = (static_cast<unsigned long long>(t) * 0x9E3779B97F4A7C15ull) ^
                                (static_cast<unsigned long long>(rd()) << 32 | rd());
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", id);
  return buf;
}

bool check_output_dir(const fs::path& dir, bool overwrite) {
  refuse_shared_folder(dir);
  std::error_code ec;
  std::string found;
  for (const char* f : kRunFiles)
    if (fs::exists(dir / f, ec)) found += (found.empty() ? "" : ", ") + std::string(f);
  if (found.empty()) return false;
  if (!overwrite)
    throw InputError(dir.string() + ": holds the results of another run (" + found +
                     "); pass --overwrite to replace them, or choose another --out");
  return true;
}

void prepare_output_dir(const fs::path& dir, bool overwrite) {
  if (check_output_dir(dir, overwrite)) set_aside_results(dir);
}

void check_output_files(const fs::path& dir) {
  for (const char* f : kRunOutputFiles) {
    std::error_code ec;
    const fs::file_status st = fs::status(dir / f, ec);
    if (!fs::exists(st) || fs::is_regular_file(st)) continue;
    // Opening a FIFO blocks until a writer comes, a folder fails with a message naming none.
    const char* kind = fs::is_directory(st) ? "a folder" : fs::is_fifo(st) ? "a FIFO" : "special";
    refuse(dir / f, std::string("is ") + kind + ", not a regular file");
  }
}

void check_finished_rows(const fs::path& csv, std::size_t rows) {
  std::ifstream in(csv);
  std::string line;
  for (std::size_t k = 0; k <= rows && std::getline(in, line); ++k) {
    const auto first = line.find_first_not_of(" \t\r");
    // Rows are kept by line count (run_output.cpp): a line without data among them would
    // push a finished row out.
    if (first == std::string::npos || line[first] == '#')
      refuse(csv.string() + ":" + std::to_string(k + 1),
             std::string(first == std::string::npos ? "a blank line" : "a comment line") +
                 (k == 0 ? " before the header" : " among the finished rows") +
                 " (fretbem writes none)");
  }
}

void validate_checkpoint(const Checkpoint& cp, const Model& m, const fs::path& file) {
  if (cp.inputs) check_input_digest(*cp.inputs, m);
  const Grid& g = m.scenario.grid;
  const InterfaceState& s = cp.state;
  const int nc = m.tangential_operator->components();
  if (int(s.traction.size()) != nc)
    refuse(file, "the state has " + std::to_string(s.traction.size()) +
                     " tangential components, the scenario " + std::to_string(nc));
  check_field(file, "pressure", s.pressure, g, true);
  for (int c = 0; c < nc; ++c) {
    check_field(file, "traction" + std::to_string(c), s.traction[c], g);
    check_field(file, "displacement" + std::to_string(c), s.displacement[c], g);
    check_field(file, "slip" + std::to_string(c), s.slip[c], g);
  }
  check_field(file, "slip_path", s.slip_path, g, true);
  check_field(file, "dissipation", s.dissipation, g);
  check_field(file, "wear", s.wear, g);
  check_field(file, "state", s.state.cast<double>(), g);
  check_field(file, "surface", cp.surface, g);
  check_scalar(file, "shift x", s.shift.x());
  check_scalar(file, "shift y", s.shift.y());
  check_scalar(file, "normal_force", s.normal_force);
  check_scalar(file, "indentation", s.indentation);
  const StepperMemory& mem = cp.memory;
  const std::size_t steps = m.path.steps.size();
  // Wear runs replay the cycle's path from step 0 for every simulated cycle.
  const std::size_t first = cp.wear ? 0 : 1;
  if (mem.next_step < first || mem.next_step > steps)
    refuse(file, "next_step = " + std::to_string(mem.next_step) + " outside [" +
                     std::to_string(first) + ", " + std::to_string(steps) +
                     "] (the scenario's load steps)");
  check_scalar(file, "dissipation total", mem.dissipation);
  check_scalar(file, "wear_volume", mem.wear_volume);
  if (mem.last_normal) check_scalar(file, "last normal load", mem.last_normal->value);
  if (mem.last_target.size() > 2 || !mem.last_target.allFinite())
    refuse(file, "last_target is not a finite 1- or 2-vector");
  for (const auto& [name, f] : mem.fields)  // a Coulomb bound is never negative
    check_field(file, "memory_field_" + name, f, g, name == "bound");
  if (cp.wear) check_wear(file, *cp.wear, m);
  try {
    (void)CyclePredictor::unflatten(cp.predictor, std::size_t(g.nx * g.ny), nc);
    (void)MasingImage::unflatten(mem.masing, g.nx, g.ny);
  } catch (const std::runtime_error& e) {
    refuse(file, e.what());
  }
}

}  // namespace fretbem
