// Reading numeric CSV files: load tables, time series read back on resume, ensemble members.
// One reader, one behaviour: '#' comment lines and blank lines are allowed anywhere, the first
// other line is the header of column names, every later line is a row of numbers.
#pragma once

#include <cstddef>
#include <filesystem>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

namespace fretbem::csv {

/// The cells of one CSV line split on commas, each trimmed of blanks (and a trailing '\r').
std::vector<std::string> split_line(std::string_view line);

/// A numeric table as read from a file.
struct Table {
  std::vector<std::string> columns;       ///< header names, in file order
  std::vector<std::vector<double>> rows;  ///< one entry per data row, columns.size() values
  std::vector<long> lines;                ///< 1-based file line of each row, for messages
  /// Index of the column called name, or -1.
  long find(std::string_view name) const;
};

struct ReadOptions {
  /// Accept "nan" (any case) and empty cells as NaN, and "inf" as +inf: files fretbem wrote
  /// itself (kx off; kx of a fully stuck periodic interface).
  bool allow_nan = false;
  /// Stop after this many data rows (resume reads only the rows a checkpoint covers).
  std::size_t max_rows = std::numeric_limits<std::size_t>::max();
};

/// The header: the first line that is neither blank nor a '#' comment.
/// Throws InputError naming the file if it cannot be read or has no header.
std::vector<std::string> read_header(const std::filesystem::path& file);

/// The whole table. Throws InputError naming FILE:LINE for a row with the wrong number of
/// cells or a cell that is not a finite number (NaN and +inf only with allow_nan).
Table read_table(const std::filesystem::path& file, const ReadOptions& options = {});

}  // namespace fretbem::csv
