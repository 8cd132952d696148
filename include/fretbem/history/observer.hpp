// Observer: the one interface through which a run reports what it does, to the files it
// writes, its progress line and its tests (docs/architecture.md, "The run drivers"). It sits
// in history/, the lowest layer that emits events: the Stepper emits the steps, the wear
// cycle simulation and its integrators (wear/) the simulated cycles, wear snapshots and
// finished wear steps. Every method does nothing unless overridden, so a writer overrides
// only the events it writes.
#pragma once

#include <string>

#include "fretbem/contact/interface_state.hpp"

namespace fretbem {

struct Model;
struct StepRecord;
struct WearCycle;       // wear/integrator.hpp
struct WearCheckpoint;  // wear/integrator.hpp

class Observer {
 public:
  virtual ~Observer() = default;

  // Steps (Stepper::run; the rows of a wear run's simulated cycles).

  /// A finished step: its record (the row of timeseries.csv) and the state after it.
  virtual void on_step(const StepRecord& /*rec*/, const InterfaceState& /*state*/,
                       const Model& /*model*/) {}
  /// The load path is complete (after its last step).
  virtual void on_finish(const InterfaceState& /*state*/, const Model& /*model*/) {}

  // Wear runs (the wear integrators, wear/integrator.hpp).

  /// Every simulated cycle, in order; ARKODE rows come after the integrator step they belong
  /// to is finished (their `accepted` flag is known only then).
  virtual void cycle(const WearCycle& /*c*/) {}
  /// Fields at N (worn depth and pressure, m and Pa): called at the geometric sequence of N.
  /// `cycle_end`: the stepper's state is the end of the simulated cycle whose rows were just
  /// written (the pressure is that state's); else it is the normal loading alone of the
  /// surface worn to N, solved for the pressure and not a row (the ODE integrators between
  /// their first and last snapshot).
  virtual void snapshot(double /*N*/, const Field& /*worn*/, const Field& /*pressure*/,
                        bool /*cycle_end*/) {}
  /// A wear step is finished and its rows and snapshots are out: the state to resume from.
  virtual void step_done(const WearCheckpoint& /*at*/) {}
  /// The simulated cycles the run is expected to take (wear/cost_estimate.hpp), known after
  /// its first steady cycle: what a progress line's ETA counts on.
  virtual void expect(double /*simulated_low*/, double /*simulated_high*/) {}
  /// A warning about the run, one line (explicit_cap_warning).
  virtual void warn(const std::string& /*line*/) {}
  /// Asked after each step_done: true ends the run there, `stopped` (a signal, for the CLI).
  virtual bool stop_requested() const { return false; }
};

}  // namespace fretbem
