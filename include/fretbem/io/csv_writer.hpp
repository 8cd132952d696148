// CsvWriter: a header row and one row of numbers per call, flushed at once, so that a killed
// run leaves every finished row readable (README "Time series").
#pragma once

#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "fretbem/core/format.hpp"

namespace fretbem::io {

class CsvWriter {
 public:
  /// Creates DIR (and parents) if needed and writes DIR/NAME.csv with the header row
  /// `columns`, replacing any old file. With append = true an existing file whose header
  /// equals `columns` is continued instead (a torn last line of a killed run is cut off);
  /// a missing file is created as without append.
  /// Throws InputError naming the path if the file cannot be opened or the header differs.
  CsvWriter(const std::filesystem::path& dir, const std::string& name,
            const std::vector<std::string>& columns, bool append = false);

  /// Writes one row (values.size() must equal the column count, else std::invalid_argument)
  /// with shortest round-trip precision; NaN as `nan`, infinities as `inf`/`-inf`.
  /// Throws std::runtime_error naming the path if the write fails (e.g. disk full).
  void row(const std::vector<double>& values);

  const std::filesystem::path& path() const { return path_; }
  std::size_t columns() const { return ncols_; }

 private:
  struct Close {
    void operator()(std::FILE* f) const { std::fclose(f); }
  };
  void write(const std::string& text);

  std::filesystem::path path_;
  std::size_t ncols_ = 0;
  std::unique_ptr<std::FILE, Close> file_;
};

}  // namespace fretbem::io
