#include "fretbem/core/stop_signal.hpp"

#include <csignal>

namespace fretbem {

namespace {

volatile std::sig_atomic_t g_signal = 0;

extern "C" void on_stop_signal(int sig) {
  g_signal = sig;
}

}  // namespace

void install_stop_signal_handlers(SecondSignal second) {
  struct sigaction sa {};
  sa.sa_handler = on_stop_signal;
  sigemptyset(&sa.sa_mask);
  // SA_RESETHAND: the handler runs once, the next signal takes the default action.
  sa.sa_flags = second == SecondSignal::kills ? SA_RESETHAND : 0;
  sigaction(SIGTERM, &sa, nullptr);
  sigaction(SIGINT, &sa, nullptr);
}

bool stop_requested() {
  return g_signal != 0;
}

int stop_signal() {
  return g_signal;
}

}  // namespace fretbem
