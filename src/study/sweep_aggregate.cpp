#include "fretbem/study/sweep_aggregate.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>

#include "fretbem/core/csv_reader.hpp"
#include "fretbem/core/format.hpp"
#include "fretbem/core/text_file.hpp"
#include "fretbem/study/member_status.hpp"

namespace fretbem {

namespace fs = std::filesystem;

namespace {

// The time-series columns a member's summary repeats from its last row, as final_<name>.
const std::vector<std::string> kFinalColumns{
    "Fx", "Ux", "kx", "contact_area", "stick_area", "slip_area", "dissipation", "wear_volume"};

// Header and last data row of a CSV file, as text: values are copied, never re-printed, so
// sweep.csv carries exactly the digits the member wrote (csv::read_table would parse them).
std::pair<std::vector<std::string>, std::vector<std::string>> header_and_last_row(
    const fs::path& file) {
  std::ifstream in(file);
  std::string header, line, last;
  if (!std::getline(in, header)) return {};
  while (std::getline(in, line))
    if (!line.empty()) last = line;
  if (last.empty()) return {};
  return {csv::split_line(header), csv::split_line(last)};
}

using Summary = std::vector<std::pair<std::string, std::string>>;  // column, text

Summary member_summary(const fs::path& dir) {
  Summary s;
  const auto [ch, cr] = header_and_last_row(dir / "cycles.csv");
  for (std::size_t i = 0; i < ch.size() && i < cr.size(); ++i) s.emplace_back(ch[i], cr[i]);
  const auto [th, tr] = header_and_last_row(dir / "timeseries.csv");
  for (const auto& name : kFinalColumns)
    for (std::size_t i = 0; i < th.size() && i < tr.size(); ++i)
      if (th[i] == name) s.emplace_back("final_" + name, tr[i]);
  return s;
}

// RFC 4180 quoting for the free-text error column.
std::string quoted(const std::string& text) {
  if (text.find_first_of(",\"\n") == std::string::npos) return text;
  std::string q = "\"";
  for (char c : text) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

// The member's grid and its predicted slip ring (study/member_grid.hpp): which members the
// study refined, and which stay under-resolved and by how much.
void write_grid(std::ostream& out, const MemberGrid& g) {
  out << ',' << g.n << ',';
  if (g.ring_cells >= 0) out << format_number(std::round(g.ring_cells * 100) / 100);
  out << ',' << quoted(g.resolution);
}

}  // namespace

SweepTally write_sweep_csv(const SweepSpec& spec) {
  struct Row {
    MemberStatus status;
    std::string word;
    Summary summary;
  };
  std::vector<Row> rows;
  std::vector<std::string> columns;  // summary columns in order of first appearance
  SweepTally tally;
  const StudyMembers members = spec.study_members();
  for (std::size_t k = 0; k < spec.members.size(); ++k) {
    const fs::path dir = members.path(k);
    Row r{read_member_status(dir), "", {}};
    const bool complete = member_complete(members, k);
    r.word = member_status_word(r.status, complete);
    if (complete) r.summary = member_summary(dir);
    tally.ok += complete, tally.failed += r.word == "failed", tally.running += r.word == "running";
    tally.missing += r.word == "missing" || r.word == "interrupted";
    for (const auto& [name, v] : r.summary)
      if (std::find(columns.begin(), columns.end(), name) == columns.end()) columns.push_back(name);
    rows.push_back(std::move(r));
  }
  create_output_folder(spec.out);
  {
    std::ostringstream out;
    out << "member,dir";
    for (const auto& a : spec.axes) out << ',' << a.key;
    out << ",status,exit_code,seconds,error,grid_n,ring_cells_predicted,resolution";
    for (const auto& c : columns) out << ',' << c;
    out << '\n';
    for (std::size_t k = 0; k < rows.size(); ++k) {
      const Row& r = rows[k];
      out << k << ',' << spec.member_dir(k).string();
      for (const auto& v : spec.members[k]) out << ',' << quoted(v);
      out << ',' << r.word << ',';
      if (r.status.present)
        out << r.status.exit_code << ',' << format_number(r.status.seconds);
      else
        out << ',';
      out << ',' << quoted(r.status.error);
      write_grid(out, spec.grids.at(k));
      std::map<std::string, std::string> by_name(r.summary.begin(), r.summary.end());
      for (const auto& c : columns) out << ',' << (by_name.count(c) ? by_name[c] : "");
      out << '\n';
    }
    // A full disk must not replace a good sweep.csv by a torn one.
    write_file_atomically(spec.out / "sweep.csv", out.str());
  }
  return tally;
}

}  // namespace fretbem
