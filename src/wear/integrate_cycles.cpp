// The reference wear integrator: cycle after cycle, tractions carried, each cycle's wear
// applied before the next.
#include <cstddef>
#include <utility>

#include "wear_rows.hpp"

namespace fretbem::wear_detail {

// A checkpoint after every cycle whose wear was applied (the last one only observes).
WearReport integrate_cycles(Model& model, WearCycles& cyc, Observer& log,
                            const WearCheckpoint* resume, long max_steps) {
  WearReport rep;
  const double N_end = model.scenario.wear.cycles;
  const auto snaps = snapshot_cycles(N_end);
  std::size_t next_snap = 0;
  double N0 = 0.0;
  long taken = 0;
  if (resume) {
    N0 = resume->N, next_snap = std::size_t(resume->next_snapshot);
    cyc.resume(resume->counters);
  } else {
    cyc.start();
  }
  if (!resume) log.expect(N_end + 1.0, N_end + 1.0);  // cycles 0..N_end
  for (double N = N0; N <= N_end; N += 1.0) {
    WearCycle c = cyc.carried(N);
    if (next_snap < snaps.size() && snaps[next_snap] <= N) {
      log.snapshot(N, cyc.worn(), cyc.pressure(), true);
      ++next_snap;
    }
    if (N < N_end) cyc.apply(c.rate);  // the last cycle observes the final surface
    c.accepted = true;
    keep(rep, std::move(c), log);
    if (N >= N_end) break;
    WearCheckpoint at;
    at.N = N + 1.0;
    at.worn = cyc.worn();
    at.counters = cyc.counters();
    at.steps = long(N) + 1;
    at.next_snapshot = long(next_snap);
    log.step_done(at);
    if ((max_steps >= 0 && ++taken >= max_steps) || log.stop_requested()) {
      rep.stopped = true;
      rep.N = N + 1.0;
      break;
    }
  }
  rep.worn = cyc.worn();
  rep.cycle_by_cycle = true;
  if (!rep.stopped) rep.N = N_end;
  rep.simulated_cycles = cyc.simulated();
  rep.rhs_evaluations = cyc.evaluations();
  rep.steps = long(rep.N);
  return rep;
}

}  // namespace fretbem::wear_detail
