// An exclusive advisory lock (flock) on a file, held for the life of the object; the kernel
// releases it on any exit of the process, SIGKILL included.
#pragma once

#include <filesystem>
#include <optional>

namespace fretbem {

class FileLock {
 public:
  /// Locks FILE (created if needed; its folder must exist). nullopt when another process holds
  /// the lock; InputError naming FILE when it cannot be created or locked at all.
  static std::optional<FileLock> try_lock(const std::filesystem::path& file);
  /// Locks FILE (created if needed), waiting while another process holds it. nullopt when it
  /// cannot be created or locked: for locks that only make work shared, never required.
  static std::optional<FileLock> wait_lock(const std::filesystem::path& file);

  FileLock(FileLock&& other) noexcept : fd_(other.fd_) { other.fd_ = -1; }
  FileLock& operator=(FileLock&& other) noexcept;
  FileLock(const FileLock&) = delete;
  FileLock& operator=(const FileLock&) = delete;
  ~FileLock();

 private:
  explicit FileLock(int fd) : fd_(fd) {}
  int fd_ = -1;
};

}  // namespace fretbem
