#include "fretbem/core/csv_reader.hpp"

#include <charconv>
#include <cmath>
#include <fstream>

#include "fretbem/core/errors.hpp"
#include "fretbem/core/text_file.hpp"

namespace fretbem::csv {

namespace fs = std::filesystem;

namespace {

constexpr std::string_view kBlanks = " \t\r\n\f\v";

std::string_view trimmed(std::string_view s) {
  const auto b = s.find_first_not_of(kBlanks);
  if (b == std::string_view::npos) return {};
  return s.substr(b, s.find_last_not_of(kBlanks) - b + 1);
}

// Blank lines and '#' comments carry no data wherever they stand.
bool is_data_line(std::string_view line) {
  const auto t = trimmed(line);
  return !t.empty() && t.front() != '#';
}

// Shown in messages: no control characters, bounded length.
std::string printable(std::string_view s) {
  std::string out;
  for (const char c : s.substr(0, 40)) {
    const auto u = static_cast<unsigned char>(c);
    out += (u < 0x20 || u == 0x7f) ? '?' : c;
  }
  return s.size() > 40 ? out + "..." : out;
}

bool is_nan_word(std::string_view s) {
  return s.size() == 3 && (s[0] | 0x20) == 'n' && (s[1] | 0x20) == 'a' && (s[2] | 0x20) == 'n';
}

double parse_cell(std::string_view s, bool allow_nan, const std::string& where) {
  if (allow_nan && (s.empty() || is_nan_word(s))) return std::numeric_limits<double>::quiet_NaN();
  const char* b = s.data() + (s.size() > 1 && s[0] == '+' ? 1 : 0);
  const char* e = s.data() + s.size();
  double v = 0.0;
  const auto [ptr, ec] = std::from_chars(b, e, v);
  // kx = +inf: a fully stuck periodic interface (StiffnessResult::kx), written as "inf".
  const bool own_infinity = allow_nan && v == std::numeric_limits<double>::infinity();
  if (s.empty() || ec != std::errc() || ptr != e || (!std::isfinite(v) && !own_infinity))
    throw InputError(where + ": '" + printable(s) + "' is not a finite number");
  return v;
}

std::ifstream open(const fs::path& file) {
  std::error_code ec;
  if (fs::is_directory(file, ec))
    throw InputError(file.string() + ": is a directory, not a CSV file");
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(file.string() + ": cannot open the CSV file");
  return in;
}

// Reads up to the header; returns its cells and leaves `line_no` at the header's line.
std::vector<std::string> header_of(std::istream& in, const fs::path& file, long& line_no) {
  std::string line;
  while (std::getline(in, line)) {
    ++line_no;
    if (line_no == 1) drop_utf8_bom(line);
    if (is_data_line(line)) return split_line(line);
  }
  throw InputError(file.string() + ": empty CSV file (no header row)");
}

}  // namespace

std::vector<std::string> split_line(std::string_view line) {
  std::vector<std::string> out;
  std::size_t pos = 0;
  while (true) {
    const auto comma = line.find(',', pos);
    out.emplace_back(trimmed(line.substr(pos, comma - pos)));
    if (comma == std::string_view::npos) break;
    pos = comma + 1;
  }
  return out;
}

long Table::find(std::string_view name) const {
  for (std::size_t i = 0; i < columns.size(); ++i)
    if (columns[i] == name) return static_cast<long>(i);
  return -1;
}

std::vector<std::string> read_header(const fs::path& file) {
  auto in = open(file);
  long line_no = 0;
  return header_of(in, file, line_no);
}

Table read_table(const fs::path& file, const ReadOptions& options) {
  auto in = open(file);
  Table t;
  long line_no = 0;
  t.columns = header_of(in, file, line_no);
  std::string line;
  while (t.rows.size() < options.max_rows && std::getline(in, line)) {
    ++line_no;
    if (!is_data_line(line)) continue;
    const auto cells = split_line(line);
    const std::string where = file.string() + ":" + std::to_string(line_no);
    if (cells.size() != t.columns.size())
      throw InputError(where + ": expected " + std::to_string(t.columns.size()) +
                       " values, found " + std::to_string(cells.size()));
    std::vector<double> row(cells.size());
    for (std::size_t c = 0; c < cells.size(); ++c)
      row[c] = parse_cell(cells[c], options.allow_nan, where);
    t.rows.push_back(std::move(row));
    t.lines.push_back(line_no);
  }
  return t;
}

}  // namespace fretbem::csv
