// The one CSV reader (core/csv_reader): comments and blank lines anywhere, exact numbers,
// FILE:LINE in every message; and a load table with a leading comment, which `check` and `run`
// must both accept.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>

#include "fretbem/core/csv_reader.hpp"
#include "fretbem/core/errors.hpp"
#include "support/temp_dir.hpp"

namespace fs = std::filesystem;
using fretbem::InputError;
namespace csv = fretbem::csv;

namespace {

const fs::path& temp_dir() {
  return fretbem_test::process_temp_dir().path();
}

fs::path write(const std::string& name, const std::string& text) {
  const fs::path p = temp_dir() / name;
  std::ofstream(p, std::ios::binary) << text;
  return p;
}

std::string message_of(const fs::path& p, csv::ReadOptions o = {}) {
  try {
    csv::read_table(p, o);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(CsvReader, SplitsAndTrimsCells) {
  const auto c = csv::split_line(" time , Fz,Fx\r");
  ASSERT_EQ(c.size(), 3u);
  EXPECT_EQ(c[0], "time");
  EXPECT_EQ(c[1], "Fz");
  EXPECT_EQ(c[2], "Fx");
  EXPECT_EQ(csv::split_line("a,,b").at(1), "");
}

TEST(CsvReader, CommentsAndBlankLinesAnywhere) {
  const auto p = write(
      "c.csv", "\xEF\xBB\xBF# a table\n\n  # indented comment\ntime,Fx\n0,1.5\n\n# mid\n1,-2e-3\n");
  EXPECT_EQ(csv::read_header(p), (std::vector<std::string>{"time", "Fx"}));
  const auto t = csv::read_table(p);
  ASSERT_EQ(t.rows.size(), 2u);
  EXPECT_EQ(t.rows[0][1], 1.5);
  EXPECT_EQ(t.rows[1][1], -2e-3);
  EXPECT_EQ(t.lines[1], 8);
  EXPECT_EQ(t.find("Fx"), 1);
  EXPECT_EQ(t.find("Fy"), -1);
}

TEST(CsvReader, NumbersReadBackExactly) {
  const auto p = write("exact.csv", "x\n0.1\n+3\n1e-300\n");
  const auto t = csv::read_table(p);
  EXPECT_EQ(t.rows[0][0], 0.1);
  EXPECT_EQ(t.rows[1][0], 3.0);
  EXPECT_EQ(t.rows[2][0], 1e-300);
}

TEST(CsvReader, BadRowsNameFileAndLine) {
  const auto ragged = write("ragged.csv", "a,b\n1,2\n3\n");
  EXPECT_NE(message_of(ragged).find("ragged.csv:3: expected 2 values, found 1"), std::string::npos);
  const auto garbage = write("garbage.csv", "a\n1\nx1\n");
  EXPECT_NE(message_of(garbage).find("garbage.csv:3: 'x1' is not a finite number"),
            std::string::npos);
  const auto nan = write("nan.csv", "a\nnan\n");
  EXPECT_NE(message_of(nan).find("is not a finite number"), std::string::npos);
  EXPECT_TRUE(std::isnan(csv::read_table(nan, {.allow_nan = true}).rows[0][0]));
  // fretbem's own files hold kx = inf for a fully stuck periodic interface; inputs may not.
  const auto inf = write("inf.csv", "a\ninf\n");
  EXPECT_NE(message_of(inf).find("is not a finite number"), std::string::npos);
  EXPECT_EQ(csv::read_table(inf, {.allow_nan = true}).rows[0][0],
            std::numeric_limits<double>::infinity());
  const auto minus_inf = write("minus_inf.csv", "a\n-inf\n");
  EXPECT_THROW(csv::read_table(minus_inf, {.allow_nan = true}), InputError);
  EXPECT_NE(message_of(write("empty.csv", "# only a comment\n\n")).find("no header"),
            std::string::npos);
  EXPECT_NE(message_of(temp_dir()).find("is a directory"), std::string::npos);
  EXPECT_NE(message_of(temp_dir() / "missing.csv").find("cannot open"), std::string::npos);
}

TEST(CsvReader, MaxRowsStopsBeforeATornLine) {
  const auto p = write("torn.csv", "a,b\n1,2\n3,4\n5,");
  EXPECT_EQ(csv::read_table(p, {.max_rows = 2}).rows.size(), 2u);
}

// `check` and `run` share the reader: a table that opens with a comment passes both.
TEST(CsvReader, LoadTableWithLeadingCommentRuns) {
  const fs::path dir = temp_dir() / "leading_comment";
  fs::create_directories(dir);
  std::ofstream(dir / "path.csv")
      << "# Fz in N, Fx in N\n\ntime,Fz,Fx\n0,10,0\n0.5,10,2\n1,10,-2\n";
  std::ofstream(dir / "s.ini") << "[material]\nE = 210e9\nnu = 0.3\nmu = 0.5\n"
                                  "[grid]\nn = 16\nlength = 2.8e-4\n"
                                  "[surface]\ntype = sphere\nradius = 0.01\n"
                                  "[load]\npath = table\ntable = path.csv\n";
  const std::string bin = FRETBEM_BINARY;
  const std::string ini = (dir / "s.ini").string();
  auto status = [](const std::string& cmd) {
    const int s = std::system((cmd + " > /dev/null 2>&1").c_str());
    return WIFEXITED(s) ? WEXITSTATUS(s) : -1;
  };
  EXPECT_EQ(status(bin + " check " + ini), 0);
  EXPECT_EQ(status(bin + " run " + ini + " --quiet --out " + (dir / "out").string()), 0);
  const auto t = csv::read_table(dir / "out" / "timeseries.csv", {.allow_nan = true});
  // Row 0 is the table's first row (normal loading, no tangential load), then one per row.
  EXPECT_EQ(t.rows.size(), 3u);
}
