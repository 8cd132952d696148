// The process-wide input-warning handler and the cautions it has not been handed yet.
#include "fretbem/core/input_warning.hpp"

#include <mutex>
#include <utility>
#include <vector>

namespace fretbem {

namespace {

struct Pending {
  std::mutex mutex;
  InputWarningHandler handler;
  std::vector<std::string> held;
};

Pending& pending() {
  static Pending p;
  return p;
}

}  // namespace

InputWarningHandler set_input_warning_handler(InputWarningHandler h) {
  Pending& p = pending();
  const std::lock_guard lock(p.mutex);
  p.held.clear();
  return std::exchange(p.handler, std::move(h));
}

void input_warning(const std::string& text) {
  Pending& p = pending();
  const std::lock_guard lock(p.mutex);
  if (p.handler) p.held.push_back(text);
}

void release_input_warnings() {
  Pending& p = pending();
  const std::lock_guard lock(p.mutex);
  for (const auto& w : p.held) p.handler(w);
  p.held.clear();
}

}  // namespace fretbem
