// A fresh folder for the files a test writes, removed with everything in it when the test is
// done. ctest runs a file's cases in parallel processes, and worktrees share one temporary
// root: each folder gets a name no other process or object can take (mkdtemp).
#pragma once

#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <system_error>

namespace fretbem_test {

/// A folder `<temp root>/fretbem_<tag>_XXXXXX` (the root: $TMPDIR or /tmp), made by the
/// constructor and removed with its contents by the destructor, unless FRETBEM_KEEP_TEST_DIRS
/// is set (non-empty): then it stays, for a look at what a failed test wrote. A forked child
/// that exits never removes its parent's folder: only the process that made it does.
class TempDir {
 public:
  explicit TempDir(const std::string& tag = "test") {
    std::string name =
        (std::filesystem::temp_directory_path() / ("fretbem_" + tag + "_XXXXXX")).string();
    if (!::mkdtemp(name.data())) throw std::runtime_error("mkdtemp failed for " + name);
    path_ = name;
  }
  ~TempDir() {
    const char* keep = std::getenv("FRETBEM_KEEP_TEST_DIRS");
    if ((keep && *keep) || ::getpid() != owner_) return;
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;

  const std::filesystem::path& path() const { return path_; }
  /// A path inside the folder (not created).
  std::filesystem::path operator/(const std::string& name) const { return path_ / name; }
  /// A path `name` inside the folder where nothing is (removed if a previous use left
  /// something): for a program that must make it itself, as `fretbem run --out` does.
  std::filesystem::path vacant(const std::string& name) const {
    const std::filesystem::path d = path_ / name;
    std::filesystem::remove_all(d);
    return d;
  }
  /// A fresh subfolder `name`: emptied if a previous use in this folder left one.
  std::filesystem::path fresh(const std::string& name) const {
    const std::filesystem::path d = path_ / name;
    std::filesystem::remove_all(d);
    std::filesystem::create_directories(d);
    return d;
  }

 private:
  std::filesystem::path path_;
  pid_t owner_ = ::getpid();
};

/// The folder of this test process, removed when the process exits: for helpers that hand
/// out paths outliving one test's scope.
inline const TempDir& process_temp_dir() {
  static const TempDir dir("process");
  return dir;
}

}  // namespace fretbem_test
