// FFTW wisdom (solver.fft_plan): where `auto` measures, and that measuring a size is
// serialised between processes, so that concurrent first runs plan from one measurement.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>
#include <thread>

#include "fretbem/elastic/fft_wisdom.hpp"
#include "fretbem/elastic/half_space.hpp"
#include "fretbem/scenario/scenario.hpp"
#include "support/child_process.hpp"
#include "support/temp_dir.hpp"

namespace fretbem {
namespace {

namespace fs = std::filesystem;

// Sets FRETBEM_FFTW_WISDOM for the life of the object, then restores the test's own value.
class WisdomFile {
 public:
  explicit WisdomFile(const std::string& value) {
    if (const char* old = std::getenv("FRETBEM_FFTW_WISDOM")) old_ = old, had_ = true;
    setenv("FRETBEM_FFTW_WISDOM", value.c_str(), 1);
  }
  ~WisdomFile() {
    if (had_)
      setenv("FRETBEM_FFTW_WISDOM", old_.c_str(), 1);
    else
      unsetenv("FRETBEM_FFTW_WISDOM");
  }

 private:
  std::string old_;
  bool had_ = false;
};

TEST(FftWisdom, AutoMeasuresOnlyWhereWisdomIsKept) {
  EXPECT_EQ(Scenario{}.solver.fft_plan, FftPlanning::estimate);  // thread-count invariant bits
  const fretbem_test::TempDir tmp("wisdom_auto");
  const fs::path& dir = tmp.path();
  {
    const WisdomFile w((dir / "sub" / "wisdom").string());  // a folder it may create
    EXPECT_TRUE(fft_wisdom::persistent(FftPrecision::float64));
  }
  {
    const WisdomFile w("");  // turned off
    EXPECT_FALSE(fft_wisdom::persistent(FftPrecision::float64));
  }
  {
    const WisdomFile w("/proc/fretbem_no_such_folder/wisdom");  // cannot be created, even as root
    EXPECT_FALSE(fft_wisdom::persistent(FftPrecision::float64));
  }
}

// Whether /proc/locks lists a flock request of process `pid` that waits (a "->" entry): the
// kernel's own word that the process is blocked on a lock.
bool waits_for_flock(pid_t pid) {
  std::ifstream in("/proc/locks");
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream words(line);
    std::string index, arrow, kind, mode, access, who;
    words >> index >> arrow >> kind >> mode >> access >> who;
    if (arrow == "->" && kind == "FLOCK" && who == std::to_string(pid)) return true;
  }
  return false;
}

// A process that needs a measured plan its wisdom file lacks waits while another holds the
// file's lock (the holder measures), then plans: it neither measures alongside nor fails. The
// lock is held by a child: a lock taken in this process would be inherited by the forked
// planner (flock belongs to the open file, which fork shares) and never released for it. The
// holder lets go only once the kernel lists the planner as waiting for the lock.
TEST(FftWisdom, MeasuringWaitsForTheProcessThatHoldsTheLock) {
  const fretbem_test::TempDir tmp("wisdom_lock");
  const fs::path& dir = tmp.path();
  const WisdomFile w((dir / "wisdom").string());
  int ready[2], release[2];
  ASSERT_EQ(::pipe(ready), 0);
  ASSERT_EQ(::pipe(release), 0);
  const pid_t holder = ::fork();
  ASSERT_GE(holder, 0);
  if (holder == 0) {
    const std::optional<FileLock> held = fft_wisdom::lock(FftPrecision::float64);
    char c = held ? 'y' : 'n';
    if (::write(ready[1], &c, 1) != 1) std::_Exit(4);
    if (::read(release[0], &c, 1) != 1) std::_Exit(5);
    std::_Exit(0);
  }
  char c = 0;
  ASSERT_EQ(::read(ready[0], &c, 1), 1);
  ASSERT_EQ(c, 'y');
  const pid_t planner = ::fork();
  ASSERT_GE(planner, 0);
  if (planner == 0) {
    // 23 x 19 cells: a size no other test plans, so the fresh wisdom cannot have it.
    const Grid g{23, 19, 1e-3 / 23};
    Material m;
    m.body1 = Body{210e9, 0.3};
    HalfSpace hs(g, m, Coupling::analogy, FftOptions{.threads = 1, .measure = true});
    Field p = Field::Ones(g.nx, g.ny), u;
    hs.normal(p, u);
    std::_Exit(u.allFinite() && fs::exists(dir / "wisdom") ? 0 : 3);
  }
  int status = 0;
  const bool waited = fretbem_test::wait_until(
      planner, [&] { return waits_for_flock(planner); }, &status);
  EXPECT_TRUE(waited) << "planned while the lock was held";
  if (::write(release[1], "r", 1) != 1) ADD_FAILURE() << "cannot release the holder";
  ASSERT_EQ(::waitpid(holder, nullptr, 0), holder);
  if (waited) {
    ASSERT_EQ(::waitpid(planner, &status, 0), planner);
  }
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 0);
  for (int fd : {ready[0], ready[1], release[0], release[1]}) ::close(fd);
}

}  // namespace
}  // namespace fretbem
