#include "fretbem/study/study_members.hpp"

namespace fretbem {

std::vector<std::string> member_run_command(const StudyMembers& members, std::size_t k,
                                            const std::filesystem::path& binary) {
  std::vector<std::string> a{binary.string(), "run",   members.scenario.string(),
                             "--quiet",       "--out", members.path(k).string()};
  for (const auto& s : members.defaults) a.insert(a.end(), {"--set", s});
  for (const auto& s : members.sets(k)) a.insert(a.end(), {"--set", s});
  return a;
}

}  // namespace fretbem
