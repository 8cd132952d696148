// The process-wide input-warning handler (see input_warning.hpp).
#include "fretbem/core/input_warning.hpp"

#include <mutex>
#include <utility>

namespace fretbem {

namespace {

std::mutex handler_mutex;

InputWarningHandler& handler() {
  static InputWarningHandler h;
  return h;
}

}  // namespace

InputWarningHandler set_input_warning_handler(InputWarningHandler h) {
  const std::lock_guard lock(handler_mutex);
  return std::exchange(handler(), std::move(h));
}

void input_warning(const std::string& text) {
  const std::lock_guard lock(handler_mutex);
  if (handler()) handler()(text);
}

}  // namespace fretbem
