// Wear integration over the cycle count N (docs/wear.md; docs/architecture.md, the wear
// driver: the cycle integrator updates the surface between cycles).
//
// The surface is updated between cycles, never within one: a cycle is simulated on a frozen
// surface (constant normal load => one normal solve, constant Coulomb bound, a tangential
// history that is exactly the Mindlin–Deresiewicz loop of that surface), and its worn depth
// w(z) is then applied, z <- z - w. Updating within a cycle would change the pressure, hence
// the bound, at every step (a normal solve per step) for a correction of relative order
// w/delta, which is 1e-6..1e-3 in fretting; and it would make the per-cycle wear map w(z) that
// the ODE integrator needs ill-defined.
//
// Modes (wear.integrator):
//  - cycle: the reference. Cycle after cycle with tractions carried (the physical history);
//    each cycle's wear is applied before the next.
//  - arkode (default): erk while wear.cycles is at most 50 explicit stability caps, dirk past
//    that (measured crossover, docs/wear.md).
//  - erk: dW/dN = w(z0 - W) for the worn depth W, explicit adaptive Runge–Kutta
//    (SUNDIALS ARKODE ERKStep), error-controlled, with the step capped by the explicit stability
//    bound dN k s_max K_max <= 1, K_max = 1.7 E*/h. The right-hand side is the
//    steady cycle of the surface: from a fresh (traction-free) state, monotone loading to the
//    path's first turning point, then one full cycle back to it. For Coulomb friction at
//    constant pressure that loop is closed from the first turning point on (Masing /
//    Mindlin–Deresiewicz), so w is a function of z alone — not of a traction state carried
//    from a different surface, which is what eroded the stick zone in the prototype.
//  - dirk: the same ODE by ARKODE ARKStep, implicit TR-BDF2 (L-stable, stiffly
//    accurate, order 2), no step cap. Newton with the
//    frozen-slip Newton matrix (WearPreconditioner: the pressure response to wear with the slip
//    of the last cycle held fixed, solved exactly by CG), or Jacobian-free Newton–Krylov
//    (SPGMR, finite-difference Jacobian-vector products of the per-cycle wear map,
//    preconditioned by the same matrix): wear.newton.
//
// On a grid distributed over MPI ranks (a HalfSpace with a distributed communicator) every
// Field here is this rank's slab (half_space.hpp) and every scalar, and every decision taken
// on one, is over all ranks: the wear layer's sums, maxima and fingerprints go through the
// grid's communicator and ARKODE's vector reductions through SUNDIALS' MPI+X vector.
#pragma once

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "fretbem/history/stepper.hpp"
#include "fretbem/wear/warm_start.hpp"

namespace fretbem {

class ResultFile;

/// One simulated cycle and what it says about the surface it ran on.
struct WearCycle {
  double N = 0.0;               ///< cycle count the simulated cycle stands for
  Field rate;                   ///< worn depth of the cycle (m per cycle)
  double energy = 0.0;          ///< energy dissipated in the cycle (J)
  double wear_volume = 0.0;     ///< worn volume of the surface it ran on, sum W h^2 (m^3)
  double max_depth = 0.0;       ///< max worn depth of that surface (m)
  double contact_radius = 0.0;  ///< sqrt(A / pi) (m)
  double stick_area = 0.0;      ///< smallest stick area in the cycle (at its peak load) (m^2)
  double peak_pressure = 0.0;   ///< max p (Pa)
  double delta = 0.0;           ///< indentation against the unworn datum (m)
  double max_slip = 0.0;        ///< largest slip path length of a node in the cycle (m)
  double simulated = 0.0;       ///< simulated cycles so far, this one included
  /// The surface it ran on is a point of the integrator's solution (cycle mode: always;
  /// ARKODE: the first evaluation of an accepted state, and the final observation), not a
  /// stage, trial or rejected evaluation. N is increasing over the accepted cycles.
  bool accepted = false;
  std::uint64_t worn_hash = 0;  ///< fingerprint of the worn depth it ran on (ARKODE only)
};

/// WearCycles' counters: what a resumed run continues from.
struct WearCounters {
  double simulated = 0.0;  ///< simulated cycles
  int evaluations = 0;     ///< simulated-cycle evaluations (wear maps)
  int rows = 0;            ///< rows emitted to the observers (timeseries.csv)
  int index = 0;           ///< simulated-cycle index (the integer part of a row's time)
};

/// Where a wear run stands after a finished wear step — a simulated cycle (cycle mode) or an
/// accepted integrator step (ARKODE) — besides the stepper state: the wear part of a
/// checkpoint (checkpoint.hpp).
struct WearCheckpoint {
  double N = 0.0;           ///< cycle count reached (cycle mode: the next cycle to simulate)
  Field worn;               ///< worn depth W at N (ARKODE; cycle mode: z0 - surface)
  double h_next = 0.0;      ///< ARKODE: step to attempt next (the first step after a resume)
  double h_max = INFINITY;  ///< ARKODE: explicit stability cap in force
  WearCounters counters;
  long steps = 0, rejected = 0;  ///< integrator steps so far (all invocations)
  long next_snapshot = 0;        ///< index into snapshot_cycles(wear.cycles)
  /// ARKODE: where the next wear-map evaluation starts (WearCycles::warm_start).
  WearWarmStart warm;
  long cycles_rows = 0;   ///< rows of cycles.csv (set by the log)
  long snapshots = 0;     ///< snapshot groups written (set by the log)
  bool implicit = false;  ///< ARKODE: the method in use (arkode chooses once, at N = 0)
  /// ARKODE: the state at N already has its accepted row (an explicit step's last stage ran
  /// on it), so the resumed run's first evaluation there is a repeat, as uninterrupted.
  bool state_has_row = false;
  /// ARKODE: the cost guard's next stretch of cycles and whether the last wear step was one
  /// (a stretch doubles while the integrator stays unprofitable).
  double stretch = 0.0;
  bool stretched = false;
  /// ARKODE: cycles of the current stretch still to simulate (a stretch runs on through the
  /// snapshots it reaches; 0: the integrator steps next).
  double stretch_left = 0.0;
  /// ARKODE: simulated cycles of the last integrator step the cost guard weighed (a stretch
  /// runs on to the snapshot when a step over the rest of the interval could not pay them).
  double step_cost = 0.0;
  bool step_unpaid = false;  ///< ARKODE: that step was not kStepWorth times cheaper
  /// ARKODE: the absolute tolerance on W in use (m; wear_detail::absolute_tolerance). Read,
  /// not recomputed, on resume: its indentation probe starts from the last evaluation's
  /// pressure there and lands within solver.tolerance of the first run's, which moves every
  /// step size chosen after an error-test failure. 0: not in the checkpoint (recomputed).
  double atol = 0.0;
};

struct WearReport {
  Field worn;                      ///< final worn depth W = z0 - z (m)
  std::vector<WearCycle> history;  ///< every simulated cycle (rate fields dropped)
  double simulated_cycles = 0.0;   ///< simulated cycles (a steady cycle counts as 1.25)
  int rhs_evaluations = 0;         ///< wear-map evaluations (cycles in cycle mode)
  long steps = 0, rejected = 0;    ///< integrator steps (arkode/dirk), all invocations
  bool implicit = false;           ///< the implicit method ran (dirk, or arkode's choice)
  bool cycle_by_cycle = false;     ///< every cycle simulated (cycle mode, or a short run)
  /// Implicit integrator: Newton iterations and their convergence failures, Krylov iterations
  /// (wear.newton = krylov), inner CG iterations (= convolutions) of the frozen-slip solves.
  long newton_iterations = 0, newton_failures = 0, krylov_iterations = 0, inner_iterations = 0;
  /// Cost guard: stretches of cycles simulated one by one where integrator steps were not
  /// cheaper, and the cycles they covered.
  long stretches = 0;
  double stretch_cycles = 0.0;
  double N = 0.0;        ///< cycle count reached
  bool stopped = false;  ///< stopped by the step budget or a signal before wear.cycles
  int exit_code = 0;     ///< of `fretbem run` (run_wear): 128 + signal when one stopped it
};

/// Simulates cycles of the scenario's load path (its first period) on the model's surface.
class WearCycles {
 public:
  WearCycles(Model& model, Stepper& stepper, std::vector<Observer*> observers = {});
  /// The initial normal loading (row 0).
  void start();
  /// One cycle continuing the stepper's history (cycle mode); the surface is not touched.
  WearCycle carried(double N);
  /// The steady cycle of surface z0 - worn, from a fresh traction state (ODE right-hand side):
  /// the virgin loading to the first turning point, then loops back to it until the loop
  /// repeats (one pass where Masing's rule closes it), the last one measured. Under
  /// solver.coupling = coupled, once a loop has run, the loops start instead from the state
  /// the last steady() or continued() ended in, carried onto this surface
  /// (steady_from_last_loop). Throws InputError when it does not repeat within
  /// kMaxSettleLoops.
  WearCycle steady(double N, const Field& worn);
  /// Loops of the steady cycle run at most to find it periodic.
  static constexpr int kMaxSettleLoops = 16;
  /// Two loops count as the same when their worn depths differ by at most the larger of
  /// kSettleShare x wear.rtol and kSettleNoise x solver.tolerance (the loops' own solver
  /// noise) of the largest, relative: the wear map is then within a tenth of the ODE's
  /// tolerance of the periodic one.
  static constexpr double kSettleShare = 0.1, kSettleNoise = 100.0;
  /// The next steady loop continuing the stepper's history after a steady() or continued()
  /// whose wear was apply()'d: one cycle of the physical history (stretches of cycles in the
  /// ODE modes).
  WearCycle continued(double N);
  /// Indentation of the unworn surface under the path's initial normal load (m): the depth
  /// scale of the wear tolerances.
  double initial_indentation();
  /// Pressure on surface z0 - worn under the scenario's normal load.
  Field pressure_on(const Field& worn);
  /// Removes one cycle's worn depth from the surface, z <- z - rate (cycle mode).
  void apply(const Field& rate);
  /// Sets the model's surface to z0 - worn (collective on a distributed grid).
  void wear_to(const Field& worn);
  /// The model surface's worn depth z0 - z (m).
  Field worn() const;
  /// Pressure of the last simulated step.
  const Field& pressure() const { return stepper_.state().pressure; }
  double simulated() const { return simulated_; }
  int evaluations() const { return evaluations_; }
  WearCounters counters() const { return {simulated_, evaluations_, row_, index_}; }
  /// Resume: continue the counters and the evaluations' warm start (empty: the next one
  /// starts cold); the stepper state was restored by the caller, and the surface changed since
  /// its last normal solve (cycle mode applies a cycle's wear before every checkpoint).
  void resume(const WearCounters& c, const WearWarmStart& warm = {});
  /// What the next steady() starts its normal-type solves from: the recent steady()s' worn
  /// depths and pressures (empty before the first). The worn surface moves little between
  /// evaluations.
  const WearWarmStart& warm_start() const { return warm_; }
  /// The next steady() is expected on the last one's worn depth moved by `worn_change` (m),
  /// with its pressure moved by about `pressure_change` (Pa): a point of its start's fit.
  void predict(const Field& worn_change, const Field& pressure_change) {
    warm_.predict(worn_change, pressure_change);
  }

 private:
  void fresh(const Field& worn, const Field& pressure = Field());
  /// The grid's reduction layer (one rank: the identity).
  const Communicator& comm() const;
  /// Largest value of a field over the grid's ranks (collective).
  double largest(const Field& x) const;
  /// Worn volume (m^3) of worn depths `worn` (m) over the grid's ranks (collective).
  double volume(const Field& worn) const;
  /// The normal loading alone of surface z0 - worn from a traction-free state, silent: its
  /// state is returned, the stepper (the run's cumulative dissipation with it) and the model's
  /// surface are left as they were.
  InterfaceState probe_loading(const Field& worn);
  WearCycle steady_from_last_loop(double N, const Field& worn);
  int settle();
  Field loop_wear();
  StepRecord step(const LoadStep& ls, double time, bool emit);
  const VecField* start_of(const LoadStep& ls) const;
  void superpose_virgin();
  /// `repeat`: each step is the stepper's repeat slot of its index (carried cycles).
  WearCycle measure(double N, const std::vector<LoadStep>& steps, double t_shift,
                    bool repeat = false);

  Model& model_;
  Stepper& stepper_;
  std::vector<Observer*> observers_;
  LoadStep initial_;
  std::vector<LoadStep> cycle_, virgin_, steady_;  // one period; to 1st turning; turning->turning
  double turn_ = 0.0;                              // time of the first turning point
  bool settles_ = false;         // the steady loop is run until it repeats (not closed at once)
  bool carries_loop_ = false;    // coupled: steady() starts from the last loop's end
  bool holds_loop_end_ = false;  // the stepper holds the end of a steady or continued loop
  // coupled, solver.predictor != none: a carried cycle's steps are the stepper's repeat slots
  bool repeats_ = false;
  double simulated_ = 0.0;
  int evaluations_ = 0, row_ = 0, index_ = 0;
  WearWarmStart warm_;
  // Masing's rule on a loop that closes at once (loop_closes_at_once) under the one-component
  // analogy: the traction at the loop's load -target_a is -traction_a, back at target_a it is
  // traction_a, the state of the first turning point (Mindlin & Deresiewicz 1953).
  bool masing_ = false;
  const LoadStep* turning_a_ = nullptr;  // the virgin loading's last step, in virgin_
  VecField traction_a_, reversed_a_;     // empty outside steady()'s loop
  VecField superposed_;                  // the virgin step's start, empty outside it
};

/// Runs wear.integrator to wear.cycles, reporting its wear events (cycle, snapshot, step_done,
/// expect, warn; stop_requested asked after each wear step) to `log`. With `resume`, continues from
/// that checkpoint (cycle mode: the caller restored the stepper state and the surface). At most
/// `max_steps` wear steps (simulated cycles in cycle mode, accepted integrator steps in
/// ARKODE modes) are taken in this call (negative: no limit), and none after the log's
/// stop_requested(); the report is then `stopped`.
WearReport integrate_wear(Model& model, WearCycles& cycles, Observer& log,
                          const WearCheckpoint* resume = nullptr, long max_steps = -1);

/// wear.integrator = arkode: the explicit method while the run is short against its stability
/// cap, the implicit one past it (wear.cycles > kImplicitPastCaps x cap). Measured
/// (docs/wear.md, simulated cycles erk vs dirk): N_end / cap = 9 (n = 32, 500 cycles): 86 vs
/// 178; 16 (n = 64, 1e4): 90 vs 144; 360 (n = 32, 2e4): 1620 vs 494; 1600 (n = 64, 1e6): 2410
/// vs 594. Interpolated crossovers: ~40 and ~100.
inline constexpr double kImplicitPastCaps = 50.0;

/// Whether the implicit method runs: dirk; arkode past kImplicitPastCaps caps, or when the cap
/// is so short that an explicit step (two wear-map evaluations of `evaluation_cycles` simulated
/// cycles each) can never cover twice its cost in cycles (the cost guard's kStepWorth): then
/// every explicit step is unprofitable and the cost guard's stretches, interrupted by one
/// wasted step per snapshot interval, exceed N (gross slip, n = 64, k = 1e-13, N = 100: cap
/// 2.8 cycles, 117.6 simulated cycles with erk, 61.2 with dirk; tools/bench/wear_sweep.py).
bool runs_implicit(WearIntegrator kind, double N, double cap, double evaluation_cycles);

/// Stability cap on the cycle step of an explicit integrator: 1 / (k_eq s_max K_max),
/// K_max = 1.7 E*/h the largest eigenvalue of the normal influence matrix.
double explicit_step_cap(const Model& model, double max_slip);

/// wear.integrator = erk chosen for a run longer than kImplicitPastCaps stability caps `cap`
/// (cycles per explicit step, of the unworn surface): a one-line warning (no "fretbem: "
/// prefix, no newline) naming the cap, the run's length in caps, and dirk / arkode; empty
/// otherwise. Printed by `fretbem check` and at the start of the run.
std::string explicit_cap_warning(const WearSpec& wear, double cap);

/// Runs this short are simulated cycle by cycle whatever wear.integrator says: an ODE
/// integrator cannot beat N + 1 simulated cycles there (its first steady cycle, one step per
/// snapshot 1, 2, 5, 10, 20 of at least two evaluations each, and the final observation):
/// measured at n = 32, Q = 0.6 mu P, k = 1e-11 (tools/bench/wear_sweep.py), arkode took 17.4
/// simulated cycles for N = 10; see docs/wear.md for the crossover.
inline constexpr double kShortRun = 20.0;

/// Whether every cycle is simulated whatever the ODE integrators could do: wear.integrator =
/// cycle, or a whole number of wear.cycles up to kShortRun.
bool simulates_every_cycle(const WearSpec& wear);

/// Explicit stability cap (cycles, explicit_step_cap) below which the ODE integrators refuse
/// a run. Cycle-by-cycle wear is a forward step of one cycle, stable on the stiffest mode only
/// while 1 cycle x k_eq s_max K_max <= 2, i.e. cap >= 0.5; below that the cycles' history
/// overshoots node by node (the contact narrows and hops between spots) and follows no
/// solution of the ODE in N. Measured on a gross-slip file sphere (n = 24, 200 cycles, k
/// varied; docs/wear.md, "Integrators"): erk within 1.3e-4 of `cycle` in max worn depth at
/// cap 0.38, -5.4 % at 0.34, -12 % at 0.021; and there `cycle` itself moves by 14-27 % when
/// its first cycle is the steady one instead of the virgin one (n = 16 sphere, cap 0.13 and
/// 0.03): no integrator in N can stand for that history.
inline constexpr double kMinOdeCap = 0.5;

/// Throws InputError naming wear.integrator when an ODE integrator (erk, dirk, arkode) meets
/// an unworn surface whose explicit stability cap `cap` is below kMinOdeCap.
void require_ode_cap(const WearSpec& wear, double cap);

/// Geometric output sequence 0, 1, 2, 5, 10, 20, 50, ... up to and including N_end.
std::vector<double> snapshot_cycles(double N_end);

/// The worn depth of each body for a total worn depth W: the indenter takes
/// wear.indenter_share of it, the half-space the rest (the contact sees only the sum).
Field indenter_worn(const Model& model, const Field& worn);
Field half_space_worn(const Model& model, const Field& worn);

}  // namespace fretbem
