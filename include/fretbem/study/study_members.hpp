// The members of a study (`fretbem sweep`, `fretbem ensemble`) as its subprocess pool runs them
// (study/member_pool.hpp): each member is a `fretbem run` of one base scenario with its own
// overrides, into its own folder below the study's.
#pragma once

#include <cstddef>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace fretbem {

struct StudyMembers {
  std::filesystem::path scenario;  ///< base scenario of every member
  std::filesystem::path out;       ///< the study's folder; member folders lie below it
  /// Overrides every member starts from, before its own, so that the member's win
  /// (solver.threads=1: members, not FFT threads, are a study's unit of parallelism).
  std::vector<std::string> defaults;
  std::size_t count = 0;
  /// Folder of member k, relative to `out` (member_0007, H0.3/seed_007).
  std::function<std::filesystem::path(std::size_t)> dir;
  /// Overrides of member k, after `defaults`: what identifies the member. Its status file
  /// records them, and a re-run keeps or continues a member only while they are unchanged.
  std::function<std::vector<std::string>(std::size_t)> sets;

  /// Folder of member k: out / dir(k).
  std::filesystem::path path(std::size_t k) const { return out / dir(k); }
};

/// The `fretbem run` command line of member k (what a user types to rerun it alone): the base
/// scenario, --quiet, --out path(k), then --set for each default and each of the member's sets.
std::vector<std::string> member_run_command(const StudyMembers& members, std::size_t k,
                                            const std::filesystem::path& binary);

}  // namespace fretbem
