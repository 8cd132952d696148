// Stepper: walks the load path. Per step: normal solve (only when the normal load or the
// surface changed) -> tangential increment (only when its load or the bound changed) -> update
// the InterfaceState -> observables -> observers (docs/architecture.md).
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "fretbem/contact/step_work.hpp"
#include "fretbem/history/cycle_predictor.hpp"
#include "fretbem/history/failed_solve.hpp"
#include "fretbem/history/masing_image.hpp"
#include "fretbem/history/model.hpp"
#include "fretbem/history/observables.hpp"
#include "fretbem/history/observer.hpp"
#include "fretbem/history/step_control.hpp"

namespace fretbem {

/// The stepper's memory between steps besides the InterfaceState: what a restart needs.
struct StepperMemory {
  std::size_t next_step = 0;
  std::optional<NormalLoad> last_normal;
  Eigen::VectorXd last_target;
  double dissipation = 0.0;
  double wear_volume = 0.0;
  /// The per-node memory the next step reads besides the InterfaceState, by name: "bound",
  /// the Coulomb bound g (Pa) the last step ended with (computed from the state at the start
  /// of that step's normal solve, so not recomputable from the state after it: a friction law
  /// that depends on the state, static_kinetic or evolving, gives another g), and under
  /// Coupling::coupled "pressure_slip0"/"pressure_slip1" (m) and, in carried wear cycles,
  /// "repeat_end<slot>_<c>" (Pa: the traction components, then the pressure; set_repeat_slot).
  /// Empty: restore recomputes the bound from the state (a fresh start, or a checkpoint written
  /// without them).
  std::map<std::string, Field> fields;
  /// MasingImage::flatten of the stepper's Masing image (empty: none recorded).
  std::vector<double> masing;
  /// load.tolerance > 0: the duration (periods) of the last step and the estimate's rate in
  /// force (step_control.hpp); empty otherwise. The last step's bound change and
  /// slip are the fields "step_bound_change" and "step_slip".
  std::vector<double> step_estimate;
  /// load.tolerance > 0: PeriodRate::flatten, the rate in force and the period being booked
  /// (step_control.hpp); empty otherwise.
  std::vector<double> step_period;
  /// load.interpolation = cubic (three-point rule, step_before.cpp): the last step's span
  /// (periods) and 1 where it joins the next on the spline; its bound and pressure changes and
  /// through-slip are the fields "before_bound_change", "before_pressure_change", "before_slip".
  std::vector<double> step_before;
};

class Stepper {
 public:
  /// A node on its bound slips in a step when its slip exceeds kSlipThreshold x sqrt(contact
  /// nodes) x the solver tolerance x the displacement scale rms |C g| (the largest one-node
  /// error the solver's rms residual allows): below that the slip is the solver's error, not
  /// motion.
  static constexpr double kSlipThreshold = 4.0;

  explicit Stepper(Model& model);
  /// Runs the remaining steps of the path (at most max_steps of them, and none after `stop`
  /// returns true), notifying the observers after each; on_finish only when the path is
  /// complete. Returns steps run.
  std::size_t run(const std::vector<Observer*>& observers, std::size_t max_steps = SIZE_MAX,
                  const std::function<bool()>& stop = {});
  /// Runs step k only (k = 0 is the initial normal loading); returns its record.
  StepRecord advance(std::size_t k);
  /// Runs one step given explicitly (wear cycles replay the path's cycle); `index` is its row.
  StepRecord advance(const LoadStep& ls, int index);
  /// The same with a predictor of the step's traction (Pa; TangentialIncrement::guess): where
  /// the tangential solve starts when it is closer than the last step's end, never what it
  /// converges to. Null: none.
  StepRecord advance(const LoadStep& ls, int index, const VecField* guess);
  /// The indenter surface (Model::surface) changed: the next step re-solves the normal contact
  /// even at an unchanged normal load (docs/architecture.md, "Skip what a scene does not
  /// need": no normal re-solve when F_z, delta and the surface did not change).
  void surface_changed() { surface_changed_ = true; }
  /// Wear runs: the wear cycle N being simulated, named when a solve fails.
  void set_wear_cycle(double N) { wear_cycle_ = N; }
  /// Under Coupling::coupled: the steps advanced next are step `slot` (>= 0) of a sequence the
  /// caller repeats (a carried wear cycle's steps); a coupled step whose load changed starts its
  /// alternation from the pressure and traction the same slot ended with one repetition
  /// earlier, and remembers its own end for the next (coupled_repeat.cpp). -1: none.
  void set_repeat_slot(int slot) { repeat_slot_ = slot; }

  const InterfaceState& state() const { return state_; }
  /// Restart support: the complete state after the last finished step, and its restoration
  /// (with the cycle predictor's memory; an empty one for checkpoints written without it).
  StepperMemory memory() const;
  const CyclePredictor& predictor() const { return predictor_; }
  void restore(const InterfaceState& state, const StepperMemory& memory,
               CyclePredictor predictor = {});
  std::size_t steps() const { return model_.path.steps.size(); }
  /// The index of the next step to run (steps() when the path is complete).
  std::size_t next_step() const { return next_; }

 private:
  bool normal_step(const LoadStep& ls, StepRecord& rec);
  void solve_normal(const LoadStep& ls, const Field& z, StepRecord& rec);
  void set_target(const LoadStep& ls, TangentialIncrement& inc) const;
  bool coupled_step(const LoadStep& ls, StepRecord& rec);
  void onto_alternation_bound(const Field* g_prev);
  [[noreturn]] void fail_coupling(StepRecord& rec, int alternations, double dp, double dt,
                                  const VecField& tau0, const VecField& u0);
  TangentialResult coupled_tangential(const LoadStep& ls, const VecField& tau0, const VecField& u0,
                                      StepRecord& rec, double floor);
  bool friction_step();
  TangentialResult solve_increment(const TangentialIncrement& inc, const VecField& tau0,
                                   const VecField& u0, StepRecord& rec);
  bool bound_after_slip(const VecField& u0, const Eigen::VectorXd& shift);
  void step_slip_vectors(const VecField& u0, const Eigen::VectorXd& dU, VecField& s,
                         const std::vector<Eigen::Index>* nodes = nullptr);
  void note_contact();
  void set_predictor_bound();
  const FixedContact* fixed_contact();
  StepSlip step_slip(const VecField& u0, const VecField& tau0, const Eigen::VectorXd& dU);
  int settle_bound(const TangentialIncrement& inc, const VecField& tau0, TangentialResult& r,
                   StepRecord& rec, double floor = 0.0);
  bool tangential_step(const LoadStep& ls, bool bound_changed, StepRecord& rec);
  Field gap_start();
  Field gap(const Field& uz, double delta);
  StepStart step_start(const StateField& before, const VecField& tau0);
  bool shortcut_applies(std::size_t k) const;
  void shortcut_step(const LoadStep& ls, StepRecord& rec);
  Field shortcut_start(int k, double target);
  double tangent_shift(int k, double target) const;
  void keep_tangent(std::size_t k, const StepRecord& rec);
  Field secant_stiffness_start(const Field& p_star_before, double U_before) const;
  Field stiffness_start(double U_before) const;
  const Field& pressure_displacement();
  [[noreturn]] void fail(const StepRecord& rec, const SolverError& e, FailedSolve f) const;
  void accumulate_slip(const VecField& u0, const VecField* tau0, const Eigen::VectorXd& dU,
                       StepRecord& rec);
  double slip_threshold();
  const Field& local_surface();
  double highest(const Field& z) const;

  // Sub-stepped rows (load.substeps) and error-controlled steps (load.tolerance; defined in
  // step_control.cpp).
  /// The step before the next one, as the embedded estimate reads it: per node its bound
  /// change (Pa) and booked slip (m), its duration and the next step's (periods).
  struct EstimateMemory {
    Field bound_change, slip;
    double span = 0.0, span_next = 0.0;
  };
  StepRecord advance_substepped(std::size_t k);
  double solve_substeps(const LoadStep& a, const LoadStep& b, int m, int k, StepRecord& last);
  double solve_controlled(const LoadStep& a, const LoadStep& b, int k, StepRecord& last);
  StepRecord estimated_substep(const LoadStep& ls, int k, double span);
  void start_substep(const LoadStep& from, const LoadStep& to, int m, int k);
  void estimate_step();
  void restore_estimate_memory(const StepperMemory& m);
  void say_depth_limit(int k, double error, double span);

  // The step before, for the three-point rule (load.interpolation = cubic; step_before.cpp).
  /// Per node the bound and pressure changes (Pa) and through-slip (m) of the last step, its
  /// span, and whether it lies on the spline with no turning point at its end.
  struct StepBeforeMemory {
    Field bound_change, pressure_change, slip;
    double span = 0.0;
    bool smooth = false;
  };
  bool three_point_applies() const;
  void begin_step_before(const LoadStep& ls);
  std::optional<StepBefore> step_before() const;
  void remember_step(const StateField* before);
  void end_step_before(const LoadStep& ls);
  void save_step_before(StepperMemory& m) const;
  void restore_step_before(const StepperMemory& m);
  bool start_from_repeat();
  void remember_repeat();
  void save_repeats(StepperMemory& m) const;
  void restore_repeats(const StepperMemory& m);

  Model& model_;
  InterfaceState state_;
  Field bound_;
  Field bound_start_;               ///< the bound before this step's normal solve (when it changed)
  Field pressure_start_;            ///< the pressure before it
  double indentation_start_ = 0.0;  ///< delta (m) before it
  bool load_moved_ = false;  ///< the normal solve followed a change of the load, not the surface
  StepWork work_;            ///< the last step's slip, pressure along it and work
  Field loss_;               ///< step_start: the fraction of the step at which a node opened
  bool bound_moved_ = false;
  Field scale_bound_;            ///< the bound slip_threshold_ belongs to
  double slip_threshold_ = 0.0;  ///< slip of a slipping node in a step at least (m)
  std::optional<NormalLoad> last_normal_;
  Eigen::VectorXd last_target_;
  double dissipation_ = 0.0;
  double wear_volume_ = 0.0;
  std::size_t next_ = 0;
  bool surface_changed_ = false;
  double wear_cycle_ = -1.0;            // < 0: not a wear run
  CyclePredictor predictor_;            ///< Model::cycle_predictor
  std::vector<char> repeated_later_;    ///< CyclePredictor::repeated_later of the path
  std::vector<char> repeated_earlier_;  ///< CyclePredictor::repeated_earlier of the path
  bool substep_predictor_ = false;      ///< substeps_predicted of the model
  MasingImage::Plan masing_plan_;       ///< MasingImage::plan of the model
  bool contact_fixed_ = false;          ///< TangentialIncrement::contact_fixed for every step
  /// With contact_fixed_: the contact nodes (g > 0) of the bound, the nodes accumulate_slip books.
  std::vector<Eigen::Index> contact_;
  long contact_edges_ = -1;     ///< contact_edges of contact_ (< 0: not counted yet)
  FixedContact fixed_contact_;  ///< fixed_contact(): contact_ and its edges
  /// work_'s slip, pressure and work are zero off contact_ (step_slip_vectors): the listed
  /// steps write them on contact_ only.
  bool work_zero_off_contact_ = false;
  double edge_load_share_ = 0.0;     ///< edge_load_share of state_.pressure (solve_normal)
  MasingImage masing_;               ///< the Masing image's virgin table and branch origin
  const VecField* guess_ = nullptr;  ///< the predictor of the step being advanced
  bool guess_continues_ = false;     ///< guess_ is the Masing image or a secant (no comparison)
  bool guess_predicted_ = false;     ///< guess_ is the cycle predictor's (CyclePredictor::find)
  /// The step being advanced is path step k on the path's first monotone segment, where the
  /// Ciavarella–Jäger shortcut holds. Only a path index says so: a step given explicitly (a
  /// wear cycle's, whose index is a row) is solved incrementally. Judged by its row index, every
  /// step of a wear cycle took the shortcut, reversals included, and the carried cycles of
  /// sweep seed 1 case 282 dissipated 25 % less than their closed loop.
  bool shortcut_ = false;
  Field shortcut_pressure_, shortcut_uz_;  ///< pressure_displacement(): p (Pa) and K p (m)
  /// p* (Pa) of the row before the last on the shortcut's segment: the secant start's second
  /// point (checkpointed; empty off the segment).
  Field shortcut_p_star_;
  /// The k_x solve's psi (Pa/m) of the last row when the next row is a shortcut row: the
  /// loading curve's tangent -mu dp*/dU there, the next corrective solve's start
  /// (checkpointed; empty otherwise).
  Field shortcut_psi_;
  /// The shortcut row's tangent -dp*/dU (Pa/m, times mu) extrapolated from the secant to the
  /// row before and that row's psi (stiffness_start, all in the checkpoint): the k_x solve's
  /// start; empty off the shortcut's rows.
  Field kx_start_;
  /// Coupling::coupled: tangential displacement (m) of the pressure at the end of the last
  /// step (the start of this one); empty until first needed (and after a restore).
  VecField pressure_slip_;
  int repeat_slot_ = -1;  ///< set_repeat_slot
  /// Per repeat slot: the traction components (Pa) and the pressure (Pa) its last coupled step
  /// ended with (checkpointed; empty until that step ran once).
  std::vector<VecField> repeat_ends_;
  /// Advancing a sub-step of a row before its last: no kx and no edge-contact refusal (the
  /// row's end has both).
  bool substep_ = false;
  const VecField* row_guess_ = nullptr;  ///< the predictor of the row being subdivided
  bool row_guess_predicted_ = false, row_guess_continues_ = false;  ///< its guess_ flags
  /// The row just advanced was solved in one step (its transition is remembered, not its
  /// sub-steps').
  bool row_whole_ = true;
  int substep_normal_iterations_ = 0, substep_tangential_iterations_ = 0;
  int substep_coupling_iterations_ = 0;
  int substeps_solved_ = 0;         ///< the row's solves so far (StepRecord::substeps)
  EstimateMemory estimate_memory_;  ///< load.tolerance > 0: the step before the next one
  PeriodRate period_rate_;          ///< load.tolerance > 0: the rate that sets a period's sub-steps
  bool estimated_ = false;          ///< the step being advanced booked an increment
  double step_work_error_ = 0.0;    ///< its estimated work error (J)
  bool depth_limit_said_ = false;
  StepBeforeMemory before_;          ///< the last step, as the next one's quadrature reads it
  double last_time_ = 0.0;           ///< the time the last step ended at (periods)
  bool last_end_on_spline_ = false;  ///< it ended on the table's spline
  bool step_on_spline_ = false;      ///< the step being advanced ends on the spline
  double step_span_ = 0.0;           ///< its span (periods)
  bool step_turning_ = false;        ///< it ends at a turning point
  bool step_booked_ = false;         ///< accumulate_slip booked it
  Field surface_slab_;               ///< local_surface on a distributed grid
};

}  // namespace fretbem
