#include "fretbem/study/member_status.hpp"

#include <cstdlib>
#include <fstream>
#include <sstream>

#include "fretbem/core/format.hpp"
#include "fretbem/core/text_file.hpp"

namespace fretbem {

namespace fs = std::filesystem;

namespace {

constexpr const char* kStatusFile = "sweep_member.txt";

}  // namespace

MemberStatus read_member_status(const fs::path& dir) {
  MemberStatus s;
  std::ifstream in(dir / kStatusFile);
  if (!in) return s;
  s.present = true;
  for (std::string line; std::getline(in, line);) {
    const auto eq = line.find('=');
    if (eq == std::string::npos) continue;
    const std::string key = line.substr(0, eq), value = line.substr(eq + 1);
    if (key == "exit_code") s.exit_code = std::atoi(value.c_str());
    if (key == "seconds") s.seconds = std::strtod(value.c_str(), nullptr);
    if (key == "error") s.error = value;
    if (key == "set") s.sets.push_back(value);
  }
  return s;
}

void write_member_status(const fs::path& dir, const MemberStatus& s) {
  std::ostringstream out;
  out << "exit_code=" << s.exit_code << "\nseconds=" << format_number(s.seconds)
      << "\nerror=" << s.error << '\n';
  for (const auto& set : s.sets) out << "set=" << set << '\n';
  write_file_atomically(dir / kStatusFile, out.str());
}

bool member_running(const MemberStatus& s) {
  return s.present && s.error == kMemberRunning;
}

bool member_stopped(const MemberStatus& s) {
  return s.present && (s.error == kMemberInterrupted || member_running(s));
}

bool member_resumable(const StudyMembers& members, std::size_t k) {
  const fs::path dir = members.path(k);
  const MemberStatus s = read_member_status(dir);
  std::error_code ec;
  return member_stopped(s) && s.sets == members.sets(k) && fs::exists(dir / "checkpoint.h5", ec);
}

bool member_complete(const StudyMembers& members, std::size_t k) {
  const fs::path dir = members.path(k);
  const MemberStatus s = read_member_status(dir);
  std::error_code ec;
  return s.present && s.exit_code == 0 && s.sets == members.sets(k) &&
         fs::exists(dir / "timeseries.csv", ec);
}

std::vector<std::size_t> pending_members(const StudyMembers& members) {
  std::vector<std::size_t> out;
  for (std::size_t k = 0; k < members.count; ++k)
    if (!member_complete(members, k)) out.push_back(k);
  return out;
}

std::string member_status_word(const MemberStatus& s, bool complete) {
  if (complete) return "ok";
  if (!s.present) return "missing";
  if (member_running(s)) return "running";
  if (member_stopped(s)) return "interrupted";
  return s.exit_code == 0 ? "missing" : "failed";
}

// Beside the member's folder rather than in it: the folder is emptied when the member starts
// afresh, and the lock must outlive that.
fs::path member_lock_file(const StudyMembers& members, std::size_t k) {
  const fs::path dir = members.dir(k);
  std::string name = ".";  // appended, not "." + ...: GCC 12 -Wrestrict false positive
  name += dir.filename().string();
  name += ".lock";
  return members.out / dir.parent_path() / name;
}

}  // namespace fretbem
