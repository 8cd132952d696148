// Child processes of a study: a `fretbem run` started with its output in a log file, and its
// exit collected without blocking.
#pragma once

#include <sys/types.h>

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace fretbem {

/// Starts argv[0] with arguments argv, stdout and stderr appended to `log`; the child's pid,
/// or -1 when it could not be started.
pid_t spawn_logged(const std::vector<std::string>& argv, const std::filesystem::path& log);

/// Exit code of a child that has ended (128 + signal when killed), nullopt while it runs.
std::optional<int> poll_child(pid_t pid);
/// Waits for the child; its exit code as poll_child.
int wait_child(pid_t pid);

/// The last non-blank line of a text file, "(no output)" when there is none.
std::string last_line(const std::filesystem::path& file);

}  // namespace fretbem
