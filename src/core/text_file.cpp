#include "fretbem/core/text_file.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <string>

#include "fretbem/core/errors.hpp"

namespace fretbem {

namespace fs = std::filesystem;

namespace {

[[noreturn]] void write_failed(const fs::path& path, int err) {
  throw std::runtime_error(path.string() + ": cannot write: " + std::strerror(err));
}

}  // namespace

void write_file_atomically(const fs::path& path, std::string_view text) {
  const fs::path tmp = path.string() + ".tmp";
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) write_failed(path, errno);
  std::size_t done = 0;
  int err = 0;
  while (done < text.size() && !err) {
    const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
    if (n < 0 && errno != EINTR) err = errno;
    if (n > 0) done += std::size_t(n);
  }
  // tmpfs and NFS may report a full disk only here.
  if (!err && ::fsync(fd) != 0 && errno != EINVAL) err = errno;
  if (::close(fd) != 0 && !err) err = errno;
  if (!err && ::rename(tmp.c_str(), path.c_str()) != 0) err = errno;
  if (err) {
    ::unlink(tmp.c_str());
    write_failed(path, err);
  }
  // The renamed entry itself made durable (POSIX rename semantics); best effort: the rename
  // is already atomic.
  const fs::path dir = path.parent_path();
  const int dfd = ::open(dir.empty() ? "." : dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dfd >= 0) {
    ::fsync(dfd);
    ::close(dfd);
  }
}

// A folder that holds everything else is never one run's results folder: `--out "$OUT/"`
// with OUT unset names the root, `--out "$HOME/$RUN"` with RUN unset the home folder, and a
// run there spreads its files among the user's (with --overwrite it sets aside any of theirs
// named like its own).
void refuse_shared_folder(const fs::path& dir) {
  std::error_code ec;
  const fs::path where = fs::weakly_canonical(fs::absolute(dir, ec), ec);
  if (ec || dir.empty()) return;
  std::string what;
  if (where == where.root_path()) what = "the root folder";
  const char* home = std::getenv("HOME");
  if (what.empty() && home && *home && where == fs::weakly_canonical(home, ec) && !ec)
    what = "the home folder ($HOME)";
  if (!what.empty())
    throw InputError(dir.string() + ": " + what +
                     " cannot be an output folder; name a folder of the run's own (--out, "
                     "output.dir)");
}

void create_output_folder(const fs::path& dir) {
  refuse_shared_folder(dir);
  std::error_code ec;
  if (!dir.empty()) fs::create_directories(dir, ec);
  if (!ec && !dir.empty() && !fs::is_directory(dir, ec))
    ec = std::make_error_code(std::errc::not_a_directory);
  if (ec) throw InputError(dir.string() + ": cannot create the output folder: " + ec.message());
}

}  // namespace fretbem
