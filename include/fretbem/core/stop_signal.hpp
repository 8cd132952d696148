// SIGTERM and SIGINT as a request to stop at the next safe point: batch systems (Slurm) send
// SIGTERM some seconds before SIGKILL at a time limit, and Ctrl-C is SIGINT. A run then
// checkpoints and says how to resume; a study stops its members and aggregates the finished.
// The flag is the one piece of process-wide state: a signal handler can only set a flag.
#pragma once

namespace fretbem {

/// How a second signal is treated.
enum class SecondSignal {
  request,  ///< one more request (studies: the parent must outlive its members)
  kills,    ///< the default action (runs: a second Ctrl-C ends a long step at once)
};

/// Installs the SIGTERM/SIGINT handlers that set the stop flag.
void install_stop_signal_handlers(SecondSignal second = SecondSignal::request);

/// True once SIGTERM or SIGINT arrived after install_stop_signal_handlers.
bool stop_requested();

/// The signal that requested the stop (SIGTERM or SIGINT), 0 if none.
int stop_signal();

}  // namespace fretbem
