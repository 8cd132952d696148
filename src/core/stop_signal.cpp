#include "fretbem/core/stop_signal.hpp"

#include <pthread.h>

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
  // A process inherits its signal mask across exec: started with SIGTERM blocked, it would
  // never see Slurm's stop and be killed at the time limit without a checkpoint. A request
  // that arrived while blocked is pending and reaches the handler here.
  sigset_t stops;
  sigemptyset(&stops);
  sigaddset(&stops, SIGTERM);
  sigaddset(&stops, SIGINT);
  pthread_sigmask(SIG_UNBLOCK, &stops, nullptr);
}

bool stop_requested() {
  return g_signal != 0;
}

int stop_signal() {
  return g_signal;
}

}  // namespace fretbem
