#include "fretbem/io/csv_writer.hpp"

#include <charconv>
#include <cmath>
#include <fstream>
#include <stdexcept>
#include <system_error>

#include "fretbem/core/errors.hpp"
#include "fretbem/core/text_file.hpp"

namespace fretbem::io {

namespace fs = std::filesystem;

namespace {

std::string header_line(const std::vector<std::string>& columns) {
  std::string line;
  for (const auto& c : columns) {
    // Names are written unquoted: a separator inside one would shift every later column.
    if (c.find_first_of(",\"\r\n") != std::string::npos)
      throw std::invalid_argument("CSV column name '" + c + "' contains a separator or quote");
    line += (line.empty() ? "" : ",") + c;
  }
  return line + "\n";
}

// Content of the file up to its last complete line, and that content's first line.
struct Existing {
  std::string header;
  std::uintmax_t complete_bytes = 0;
};

Existing read_existing(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  Existing e;
  const auto last_nl = text.rfind('\n');
  e.complete_bytes = last_nl == std::string::npos ? 0 : last_nl + 1;
  const auto first_nl = text.find('\n');
  if (first_nl != std::string::npos) e.header = text.substr(0, first_nl + 1);
  return e;
}

}  // namespace

CsvWriter::CsvWriter(const fs::path& dir, const std::string& name,
                     const std::vector<std::string>& columns, bool append)
    : path_(dir / (name + ".csv")), ncols_(columns.size()) {
  const std::string header = header_line(columns);
  std::error_code ec;
  create_output_folder(dir);
  // A file without one complete line (torn header) is simply rewritten.
  const Existing old = append && fs::exists(path_, ec) ? read_existing(path_) : Existing{};
  const bool resume = old.complete_bytes > 0;
  if (resume) {
    if (old.header != header)
      throw InputError(path_.string() + ": cannot append, its header row differs");
    fs::resize_file(path_, old.complete_bytes, ec);
    if (ec) throw InputError(path_.string() + ": cannot append: " + ec.message());
  }
  file_.reset(std::fopen(path_.c_str(), resume ? "ab" : "wb"));
  if (!file_) throw InputError(path_.string() + ": cannot open for writing");
  if (!resume) write(header);
}

void CsvWriter::row(const std::vector<double>& values) {
  if (values.size() != ncols_)
    throw std::invalid_argument(path_.string() + ": row of " + std::to_string(values.size()) +
                                " values for " + std::to_string(ncols_) + " columns");
  std::string line;
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (i) line += ',';
    line += format_number(values[i]);
  }
  write(line + "\n");
}

void CsvWriter::write(const std::string& text) {
  const bool ok = std::fwrite(text.data(), 1, text.size(), file_.get()) == text.size() &&
                  std::fflush(file_.get()) == 0;
  if (!ok) throw std::runtime_error(path_.string() + ": write failed");
}

}  // namespace fretbem::io
