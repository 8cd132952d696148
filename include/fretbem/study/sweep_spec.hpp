// A parameter study: a base scenario, fixed overrides and the keys to vary, read from
// a study file. The members are the Cartesian product (or the zip) of the varied values; each
// member is the base scenario with `--set key=value` overrides.
//
// Study file (INI, '#' or ';' starts a comment):
//   [study]
//   scenario = rough.ini          ; base scenario, relative to the study file
//   out      = out/my_study       ; optional; default out/sweep_<study file stem>
//   combine  = product            ; product (first key varies slowest) or zip
//   set      = solver.tolerance=1e-9   ; optional fixed override, repeatable
//   max_grid_n = 512              ; optional: refine members whose slip ring is under 2 cells
//   [vary]
//   load.amplitude = 0.2, 0.5           ; a list
//   surface.seed   = linear(1, 3, 3)    ; n values from a to b, equally spaced
//   load.normal_force = log(0.1, 10, 5) ; n values from a to b, equally spaced in log
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "fretbem/study/study_members.hpp"

namespace fretbem {

/// Most members a study may have (as many as one range may hold); more are refused before
/// the product is formed.
inline constexpr double kMaxSweepMembers = 1e6;

struct SweepAxis {
  std::string key;                  ///< scenario key, section.name
  std::vector<std::string> values;  ///< as passed to --set (numbers in shortest round-trip form)
};

/// The grid a member runs with and what it resolves of the slip ring (history/resolution.hpp's
/// Hertz prediction; spheres under a constant normal load and a cyclic tangential load only).
struct MemberGrid {
  int n = 0;       ///< grid.n the member runs with
  int base_n = 0;  ///< grid.n of the member's scenario before the study refined it
  /// Predicted slip-ring width at the load peaks on grid n, in cells; negative: no prediction
  /// (not a sphere, no cyclic tangential load) or gross slip (the whole contact slips).
  double ring_cells = -1;
  /// sweep.csv's `resolution`: "" (no prediction), "resolved", "refined from N", "gross slip",
  /// or "under-resolved: needs grid.n >= N".
  std::string resolution;
};

struct SweepSpec {
  std::filesystem::path study_file;
  std::filesystem::path scenario;  ///< base scenario (absolute or relative to the cwd)
  std::filesystem::path out;       ///< the study's output directory
  std::vector<std::string> sets;   ///< fixed overrides applied before the varied ones
  bool zip = false;
  std::vector<SweepAxis> axes;
  std::vector<std::vector<std::string>> members;  ///< values per member, one per axis
  /// [study] max_grid_n: members whose slip ring spans under kMinRingCells cells run on the
  /// smallest multiple of 8 that resolves it, up to this; 0: every member keeps its grid.
  int max_grid_n = 0;
  std::vector<MemberGrid> grids;  ///< per member (after load_sweep_spec)

  /// --set overrides of member k: the fixed ones, then key=value per axis, then grid.n=N
  /// when the study refined its grid.
  std::vector<std::string> member_sets(std::size_t k) const;

  /// Directory of member k below `out`: member_0007 (zero-padded to the member count's width).
  std::filesystem::path member_dir(std::size_t k) const;

  /// The members as the study's pool runs them (solver.threads=1 before each member's sets);
  /// refers to this spec, which must outlive it.
  StudyMembers study_members() const;
};

/// Values of one [vary] entry: "a, b, c", "linear(a, b, n)" or "log(a, b, n)". Numbers are
/// rewritten in shortest round-trip form (so "0.50" and "0.5" are the same value); other
/// words stay as written. InputError naming `key` on a malformed entry.
std::vector<std::string> parse_sweep_values(const std::string& key, const std::string& text);

/// Reads and checks a study file: base scenario present, at least one varied key, zip axes of
/// equal length, no member twice (the same values twice would run the same member twice), and
/// every member's scenario valid (load_scenario with its overrides). `extra_sets` (the
/// command line's --set) follow the file's fixed overrides; `out` (--out) replaces the file's.
SweepSpec load_sweep_spec(const std::filesystem::path& file,
                          const std::vector<std::string>& extra_sets = {},
                          const std::filesystem::path& out = {});

}  // namespace fretbem
