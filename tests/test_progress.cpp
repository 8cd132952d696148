// The progress report: in place ('\r') only on a terminal; plain lines in a file or a batch
// log (a run with stderr in a file must not write dozens of '\r' updates onto one line).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <string>

#include "fretbem/core/progress.hpp"

namespace {

std::string contents(std::FILE* f) {
  std::rewind(f);
  std::string s;
  for (int c; (c = std::fgetc(f)) != EOF;) s += char(c);
  return s;
}

}  // namespace

TEST(Progress, PlainLinesWhenNotATerminal) {
  std::FILE* f = std::tmpfile();
  ASSERT_NE(f, nullptr);
  {
    fretbem::ProgressReporter p(true, f, {0.0, 0.0, 0.0});
    p.update("step 1/4", 0.25);
    p.update("step 2/4", 0.5);
  }
  const std::string s = contents(f);
  EXPECT_EQ(s.find('\r'), std::string::npos);
  EXPECT_NE(s.find("step 1/4  elapsed "), std::string::npos);
  EXPECT_NE(s.find("ETA "), std::string::npos);
  EXPECT_EQ(std::count(s.begin(), s.end(), '\n'), 2);
  std::fclose(f);
}

TEST(Progress, RateLimitedAndSilentWhenDisabledOrShort) {
  std::FILE* f = std::tmpfile();
  ASSERT_NE(f, nullptr);
  {
    fretbem::ProgressReporter log(true, f, {0.0, 0.0, 3600.0});  // one line per hour
    for (int i = 0; i < 100; ++i) log.update("step", 0.5);
    fretbem::ProgressReporter quiet(false, f, {0.0, 0.0, 0.0});
    quiet.update("quiet", 0.5);
    fretbem::ProgressReporter shortrun(true, f);  // nothing before the first second
    shortrun.update("short", 0.5);
  }
  const std::string s = contents(f);
  EXPECT_EQ(std::count(s.begin(), s.end(), '\n'), 1);
  EXPECT_EQ(s.find("quiet"), std::string::npos);
  EXPECT_EQ(s.find("short"), std::string::npos);
  std::fclose(f);
}
