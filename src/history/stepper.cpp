#include "fretbem/history/stepper.hpp"

#include <array>
#include <cmath>
#include <limits>

#include "fretbem/contact/contact_entry.hpp"
#include "fretbem/contact/monotone_shortcut.hpp"
#include "fretbem/core/format.hpp"
#include "fretbem/core/input_warning.hpp"
#include "fretbem/history/resolution.hpp"
#include "fretbem/history/slab_measures.hpp"

namespace fretbem {

namespace {

// One normal load on every step of the path, no wear to move the surface and a bound that
// does not evolve (a kinetic coefficient of 0 would open nodes): the contact nodes of step 0
// are those of every increment.
bool contact_never_changes(const Model& m) {
  const std::vector<LoadStep>& s = m.path.steps;
  if (m.wear || m.friction->evolves() || m.half_space->cross_coupled() || s.empty()) return false;
  for (const LoadStep& step : s)
    if (!(step.normal == s[0].normal)) return false;
  return true;
}

}  // namespace

Stepper::Stepper(Model& model)
    : model_(model), state_(InterfaceState::zeros(*model.tangential_operator)) {
  if (model_.cycle_predictor) {
    repeated_later_ = CyclePredictor::repeated_later(model_.path.steps);
    repeated_earlier_ = CyclePredictor::repeated_earlier(model_.path.steps);
  }
  substep_predictor_ = substeps_predicted(model_);
  set_predictor_bound();
  masing_plan_ = MasingImage::plan(model_);
  contact_fixed_ = contact_never_changes(model_);
  predictor_.set_communicator(model_.half_space->communicator());
  masing_.set_communicator(model_.half_space->communicator());
}

std::size_t Stepper::run(const std::vector<Observer*>& observers, std::size_t max_steps,
                         const std::function<bool()>& stop) {
  std::size_t done = 0;
  for (std::size_t k = next_; k < steps() && done < max_steps && !(stop && stop()); ++k, ++done) {
    const StepRecord rec = advance(k);
    for (auto* o : observers) o->on_step(rec, state_, model_);
  }
  if (next_ == steps())
    for (auto* o : observers) o->on_finish(state_, model_);
  return done;
}

StepperMemory Stepper::memory() const {
  StepperMemory m{next_, last_normal_, last_target_, dissipation_, wear_volume_,
                  {},    {},           {},           {},           {}};
  if (bound_.size() > 0) m.fields["bound"] = bound_;
  m.masing = masing_.flatten();
  if (model_.scenario.load.tolerance > 0.0) {
    m.step_period = period_rate_.flatten();
    m.step_estimate = {estimate_memory_.span, m.step_period[0]};
    // None before the first estimated step (row 0 is the normal load alone): a checkpoint
    // holds grid fields only, and a resume starts the estimate afresh without them.
    if (estimate_memory_.slip.size() > 0) {
      m.fields["step_bound_change"] = estimate_memory_.bound_change;
      m.fields["step_slip"] = estimate_memory_.slip;
    }
  }
  save_step_before(m);
  save_repeats(m);
  for (std::size_t c = 0; c < pressure_slip_.size(); ++c)
    m.fields["pressure_slip" + std::to_string(c)] = pressure_slip_[c];
  if (shortcut_p_star_.size() > 0) m.fields["shortcut_p_star"] = shortcut_p_star_;
  if (shortcut_psi_.size() > 0) m.fields["shortcut_psi"] = shortcut_psi_;
  return m;
}

void Stepper::restore(const InterfaceState& state, const StepperMemory& m,
                      CyclePredictor predictor) {
  state_ = state;
  predictor_ = std::move(predictor);
  const HalfSpace& hs = *model_.half_space;
  masing_ = MasingImage::unflatten(m.masing, hs.grid().nx, hs.local_rows());
  predictor_.set_communicator(hs.communicator());
  set_predictor_bound();
  masing_.set_communicator(hs.communicator());
  const auto bound = m.fields.find("bound");
  if (bound != m.fields.end())
    bound_ = bound->second;
  else
    model_.friction->bound(state_, bound_);
  note_contact();
  edge_load_share_ = edge_load_share(state_.pressure, hs);
  next_ = m.next_step;
  last_normal_ = m.last_normal;
  last_target_ = m.last_target;
  dissipation_ = m.dissipation;
  wear_volume_ = m.wear_volume;
  restore_estimate_memory(m);
  restore_step_before(m);
  restore_repeats(m);
  pressure_slip_.clear();
  const auto w0 = m.fields.find("pressure_slip0"), w1 = m.fields.find("pressure_slip1");
  if (w0 != m.fields.end() && w1 != m.fields.end()) pressure_slip_ = {w0->second, w1->second};
  const auto p_star = m.fields.find("shortcut_p_star");
  shortcut_p_star_ = p_star != m.fields.end() ? p_star->second : Field();
  const auto psi = m.fields.find("shortcut_psi");
  shortcut_psi_ = psi != m.fields.end() ? psi->second : Field();
}

// The predictor's memory bound: rows' sub-steps are remembered only where they take it.
void Stepper::set_predictor_bound() {
  predictor_.set_bytes_per_cell(substep_predictor_
                                    ? predictor_bytes_per_cell(model_.scenario, model_.path)
                                    : CyclePredictor::kBytesPerCell);
}

StepRecord Stepper::advance(std::size_t k) {
  const std::vector<LoadStep>& steps = model_.path.steps;
  const bool predict = model_.cycle_predictor && k > 0;
  const HalfSpace& hs = *model_.half_space;
  guess_ = predict ? predictor_.find(steps.at(k - 1), steps.at(k), hs.grid().nx, hs.local_rows())
                   : nullptr;
  shortcut_ = k > 0 && shortcut_applies(k);
  if (!shortcut_) shortcut_p_star_ = Field();  // the secant start holds on the segment only
  const MasingImage::Plan& mp = masing_plan_;
  const VecField* start = nullptr;
  if (!mp.image.empty() && mp.image[k]) start = masing_.branch_start(mp.level[k], bound_);
  if (!mp.virgin.empty() && mp.virgin[k] && !guess_)
    start = masing_.virgin_start(mp.level[k], bound_);
  guess_continues_ = start != nullptr;
  if (start) guess_ = start;
  guess_predicted_ = guess_ && !start;
  const bool substepped = model_.scenario.load.tolerance > 0.0 || fixed_substeps(model_) > 1;
  row_whole_ = true;
  const StepRecord rec = substepped && k > 0 ? advance_substepped(k) : advance(steps.at(k), int(k));
  keep_tangent(k, rec);
  guess_ = nullptr, guess_continues_ = false, guess_predicted_ = false;
  shortcut_ = false;
  if (!mp.virgin.empty() && mp.virgin[k])
    masing_.record_virgin(mp.level[k], state_.traction[0], bound_, mp.branches);
  if (!mp.image.empty() && mp.image[k])
    masing_.record_branch(mp.level[k], state_.traction[0], bound_);
  if (!mp.turning.empty() && mp.turning[k]) masing_.record_turning(mp.level[k], state_.traction[0]);
  // Only transitions the path repeats are remembered: nothing on a table that never repeats,
  // nothing in the last cycle of a sine. A row in sub-steps that take the predictor remembers
  // those instead (solve_substeps).
  if (predict && repeated_later_.at(k) && (row_whole_ || !substep_predictor_))
    predictor_.remember(steps[k - 1], steps[k], state_.traction, bound_);
  next_ = k + 1;
  return rec;
}

StepRecord Stepper::advance(const LoadStep& ls, int k, const VecField* guess) {
  guess_ = guess;
  struct Reset {
    const VecField*& g;
    ~Reset() { g = nullptr; }
  } reset{guess_};
  return advance(ls, k);
}

StepRecord Stepper::advance(const LoadStep& ls, int k) {
  HalfSpace& hs = *model_.half_space;
  const auto conv0 = hs.convolutions();
  StepRecord rec;
  rec.step = k;
  rec.time = ls.time;
  rec.cycle = ls.cycle;
  rec.turning = ls.turning;
  begin_step_before(ls);
  bool incremented = false;
  if (hs.cross_coupled()) {
    incremented = coupled_step(ls, rec);
  } else {
    bool bound_changed = normal_step(ls, rec);
    bound_moved_ = bound_changed;
    if (!bound_changed && k > 0 && model_.friction->evolves()) bound_changed = friction_step();
    if (shortcut_)
      shortcut_step(ls, rec), incremented = true;
    else if (k > 0)
      incremented = tangential_step(ls, bound_changed, rec);
  }
  // No increment (the initial loading, an unchanged load): nothing slips in this step.
  if (!incremented) state_.classify(bound_, model_.scenario.solver.tolerance, Field(), 0.0);
  end_step_before(ls);
  rec.Fz = state_.normal_force;
  rec.delta = state_.indentation;
  const TangentialOperator& op = *model_.tangential_operator;
  Eigen::VectorXd Floc(op.components());
  for (int c = 0; c < op.components(); ++c)
    Floc(c) = state_.traction[c].sum() * op.grid().cell_area();
  hs.communicator().sum({Floc.data(), std::size_t(Floc.size())});
  const Vec2 Fg = op.to_global(Floc);
  rec.Fx = Fg.x() + 0.0, rec.Fy = Fg.y() + 0.0;  // + 0.0: no -0 in the output
  rec.Ux = state_.shift.x() + 0.0, rec.Uy = state_.shift.y() + 0.0;
  measure_areas(state_, op, hs, rec, fixed_contact());
  rec.kx = std::numeric_limits<double>::quiet_NaN();
  if (!substep_ && stiffness_wanted(model_, k, ls.turning))
    rec.kx = model_.stiffness->solve(state_.state, shortcut_ ? &kx_start_ : nullptr).kx;
  rec.edge_load_share = model_.scenario.grid.periodic ? 0.0 : edge_load_share_;
  rec.dissipation = dissipation_;
  rec.wear_volume = wear_volume_;
  rec.convolutions = int(hs.convolutions() - conv0);
  // A solved step: no refusal of the inputs can precede its cautions any more (step 0's
  // edge-contact refusal comes after its normal solve).
  release_input_warnings();
  return rec;
}

// The contact nodes of the bound, read by accumulate_slip and measure_areas where the contact
// does not change.
void Stepper::note_contact() {
  contact_.clear();
  contact_edges_ = -1;
  if (!contact_fixed_) return;
  for (Eigen::Index k = 0; k < bound_.size(); ++k)
    if (bound_(k) > 0.0) contact_.push_back(k);
}

// The contact of a run whose contact does not change, for measure_areas (null otherwise); its
// edges counted once, on the first classified state (open exactly off contact_).
const FixedContact* Stepper::fixed_contact() {
  if (!contact_fixed_) return nullptr;
  if (contact_edges_ < 0) contact_edges_ = contact_edges(state_.state, *model_.half_space);
  fixed_contact_ = {contact_, contact_edges_};
  return &fixed_contact_;
}

// A solve failed after every fallback: name the step and cycle (and the wear cycle of a wear
// run) and hand the inputs to the caller, which writes them to DIR/failed_solve.h5.
void Stepper::fail(const StepRecord& rec, const SolverError& e, FailedSolve f) const {
  std::string where = "step " + std::to_string(rec.step) + ", cycle " + std::to_string(rec.cycle);
  if (wear_cycle_ >= 0.0) where = "wear cycle N = " + format_count(wear_cycle_) + ", " + where;
  f.scenario = model_.scenario.resolved_text;
  throw IncrementFailure(where + ": " + e.what(), std::move(f), model_.scenario.output.dir);
}

// Normal solve, skipped when neither the normal load nor the surface changed. Returns whether
// the Coulomb bound mu p changed.
bool Stepper::normal_step(const LoadStep& ls, StepRecord& rec) {
  if (last_normal_ && *last_normal_ == ls.normal && !surface_changed_) return false;
  // Only a load that moves within the step moves the contact within it: a worn surface
  // changed between steps, so what it brings into contact touched at the step's start.
  load_moved_ = last_normal_.has_value() && !surface_changed_;
  indentation_start_ = state_.indentation;
  solve_normal(ls, local_surface(), rec);
  return true;
}

// The normal solve against the gap of height z (the surface, or under Coupling::coupled the
// surface less the normal displacement of the tractions); updates the pressure, F_z, delta and
// the bound.
void Stepper::solve_normal(const LoadStep& ls, const Field& z, StepRecord& rec) {
  NormalSolver& ns = *model_.normal;
  // The solver measures delta from first touch at max(z); a worn surface's highest point may
  // lie below the original one, so delta is converted to the unworn surface's datum (its
  // growth under constant normal force is the wear's signature).
  const double datum = model_.surface0.maxCoeff() - highest(z);
  Field start = state_.pressure;
  NormalResult r;
  try {
    r = ls.normal.force_control ? ns.solve_force(z, ls.normal.value, state_.pressure)
                                : ns.solve_indentation(z, ls.normal.value - datum, state_.pressure);
  } catch (const SolverError& e) {
    FailedSolve f;
    f.solve = "normal";
    f.control = ls.normal.force_control ? "force" : "indentation";
    f.target = Eigen::VectorXd::Constant(1, ls.normal.value - (f.control == "force" ? 0 : datum));
    f.surface = z, f.pressure_start = start;
    fail(rec, e, std::move(f));
  }
  last_normal_ = ls.normal;
  surface_changed_ = false;
  state_.normal_force = r.force;
  state_.indentation = r.indentation + datum;
  bound_start_.swap(bound_);  // the bound and pressure at the step's start (step_work)
  pressure_start_ = std::move(start);
  model_.friction->bound(state_, bound_);
  note_contact();
  edge_load_share_ = edge_load_share(state_.pressure, *model_.half_space);
  // Rows are what `fretbem check` judges (from the table's rows): a sub-step within a row is
  // not refused apart, so that run and check name the same step and share.
  if (!substep_)
    check_edge_contact(model_.scenario, edge_load_share_, "step " + std::to_string(rec.step));
  rec.normal_iterations = r.iterations;
  rec.normal_residual = r.residual;
}

// A friction law that evolves moves the bound between steps: static/kinetic from the last
// step's states (the step's bound then counts as fixed, the dissipation takes g |s|); a law
// that settles its bound within the step (evolving) starts it from the last step's end and
// takes the trapezoid (settle_bound). Returns whether the bound changed.
bool Stepper::friction_step() {
  if (model_.friction->settles_within_step()) {
    // The bound moves within the step (settle_bound): its start is the last step's end.
    bound_start_ = bound_, pressure_start_ = state_.pressure;
    bound_moved_ = true, load_moved_ = false;
  }
  Field g;
  model_.friction->bound(state_, g);
  if (!model_.half_space->communicator().any(!(g == bound_).all())) return false;
  bound_.swap(g);
  return true;
}

// One tangential increment, skipped when neither its load nor the bound changed (the QP's
// solution is then the previous traction). Returns whether an increment ran.
bool Stepper::tangential_step(const LoadStep& ls, bool bound_changed, StepRecord& rec) {
  TangentialOperator& op = *model_.tangential_operator;
  TangentialIncrement inc;
  const VecField tau0 = state_.traction, u0 = state_.displacement;
  inc.bound = &bound_;
  inc.tau0 = &tau0;
  inc.u0 = &u0;
  inc.guess = guess_;
  inc.guess_continues = guess_continues_;
  inc.contact_fixed = contact_fixed_;
  VecField predicted;
  if (guess_ && guess_predicted_ && bound_moved_) {
    predicted = *guess_;
    CyclePredictor::onto_moved_bound(
        bound_, model_.half_space->communicator().max(bound_.maxCoeff()), predicted);
    inc.guess = &predicted;
  }
  set_target(ls, inc);
  const bool same_load = last_target_.size() == inc.target.size() &&
                         (inc.control == TangentialControl::force ? last_target_ == inc.target
                                                                  : inc.target.isZero(0.0));
  last_target_ = inc.target;
  if (same_load && !bound_changed) return false;
  TangentialResult r = solve_increment(inc, tau0, u0, rec);
  int iterations = r.iterations;
  // Nodes the growing contact took in part-way through the step stick from where they
  // touched (contact/contact_entry.hpp): the increment again, from its own solution, against
  // the reference with their free motion before that taken out. Not in wear runs: the wear
  // cycles restore and re-solve states on frozen surfaces, and with the correction the ODE
  // integrators and cycle-by-cycle wear parted by 2 % in worn volume under a varying normal
  // load (WearPaths.VaryingNormalLoadOdeMatchesCycleMode; within 1e-3 without it).
  VecField u0e;
  Field theta;
  if (!model_.wear && load_moved_ && bound_moved_ &&
      model_.half_space->communicator().any(
          entry_fraction(gap_start(), pressure_start_, state_.pressure,
                         model_.half_space->normal_self(), theta))) {
    entry_reference(theta, r.shift, state_.displacement, state_.traction, op.self_compliance(), u0,
                    u0e);
    inc.u0 = &u0e;
    inc.guess = nullptr;
    r = solve_increment(inc, tau0, u0e, rec);
    iterations += r.iterations;
  }
  iterations += settle_bound(inc, tau0, r, rec);
  rec.tangential_iterations = iterations;
  rec.tangential_residual = r.residual;
  state_.shift += op.to_global(r.shift);
  accumulate_slip(*inc.u0, &tau0, r.shift, rec);
  return true;
}

// The normal gap (m) at the start of the step: the separation z_max - z less the approach,
// plus the normal displacement of the start pressure (one convolution; recomputed rather than
// kept from the last normal solve so that a resumed run repeats the uninterrupted one).
Field Stepper::gap_start() {
  Field uz;
  model_.half_space->normal(pressure_start_, uz);
  return gap(uz, indentation_start_);
}

// The normal gap (m) for the normal displacement uz (m) at the approach delta (m, the unworn
// surface's datum).
Field Stepper::gap(const Field& uz, double delta) {
  const Field& z = local_surface();
  const double top = highest(z), datum = model_.surface0.maxCoeff() - top;
  return uz + (top - z) - (delta - datum);
}

// The start of a step whose bound moved, for the quadrature of the work (step_work.hpp): with
// the fraction of the step at which each node that lost contact in it opened, where the load
// moved the contact (as for contact entry, not in wear runs), from the gap at the step's end
// (the normal solve's own displacement: no convolution).
StepStart Stepper::step_start(const StateField& before, const VecField& tau0) {
  StepStart start{bound_start_, pressure_start_, before, tau0};
  if (model_.wear || !load_moved_ || model_.half_space->cross_coupled()) return start;
  loss_fraction(gap(model_.normal->displacement(), state_.indentation), pressure_start_,
                state_.pressure, model_.half_space->normal_self(), loss_);
  start.loss = &loss_;
  start.tangential_self = model_.tangential_operator->self_compliance();
  return start;
}

// The increment's control and target in the operator's components: the shift increment from
// the current shift, or the force (relative targets in units of mu F_z of the current state).
void Stepper::set_target(const LoadStep& ls, TangentialIncrement& inc) const {
  const TangentialOperator& op = *model_.tangential_operator;
  if (ls.control == Control::displacement) {
    inc.control = TangentialControl::displacement;
    inc.target = op.to_local(ls.target - state_.shift);
  } else {
    inc.control = TangentialControl::force;
    const double scale = ls.relative ? model_.scenario.material.mu * state_.normal_force : 1.0;
    inc.target = op.to_local(ls.target * scale);
  }
}

// solver.monotone = shortcut: steps on the virgin monotone segment that starts at step 0, at
// constant normal load, with the one-component analogy operator.
bool Stepper::shortcut_applies(std::size_t k) const {
  const Model& m = model_;
  return m.scenario.solver.monotone == MonotoneMethod::shortcut && !m.friction->evolves() &&
         m.tangential_operator->components() == 1 &&
         m.scenario.solver.coupling == Coupling::analogy && m.path.monotone(0, k);
}

// Warm start of the shortcut's corrective solve: the previous row's p* = p - |tau| / mu (from
// p itself the solve starts a whole segment away, slower than incremental steps), followed
// along the loading curve's tangent at that row, p*_start = p*_1 - psi dU / mu with psi the
// row's k_x solution (dp*/dU = -psi / mu, secant_stiffness_start) and dU the shift to this
// row's load (tangent_shift), else extrapolated along the secant through the row before it,
// p*_start = p*_1 + r (p*_1 - p*_2), r the ratio of the load increments (p* is a function of
// Q* or delta*, both linear in the path's target). Both are exact while the stick set holds,
// where p* is linear in the load; the tangent also holds at the row's own set where the secant
// averages over the nodes that left in between. psi and p*_2 are checkpointed, so a resumed run
// starts every solve where the uninterrupted one did. Error-controlled steps (load.tolerance)
// solve sub-steps between the path's rows, whose loads the path's ratio does not describe: they
// start from p*_1 alone.
Field Stepper::shortcut_start(int k, double target) {
  const Material& mat = model_.scenario.material;
  Field p_star = (state_.pressure - state_.traction[0].abs() / mat.mu).max(0.0);
  Field start = p_star;
  const std::vector<LoadStep>& steps = model_.path.steps;
  const bool rows = model_.scenario.load.tolerance <= 0.0;
  const double dU = rows ? tangent_shift(k, target) : std::numeric_limits<double>::quiet_NaN();
  if (std::isfinite(dU)) {
    start = (p_star - (dU / mat.mu) * shortcut_psi_).max(0.0);
  } else if (rows && k >= 2 && shortcut_p_star_.size() == p_star.size()) {
    const Vec2 e = model_.tangential_operator->direction();
    const LoadStep &a = steps.at(k - 2), &b = steps.at(k - 1), &c = steps.at(k);
    const double db = e.dot(b.target - a.target), dc = e.dot(c.target - b.target);
    const bool same = a.control == c.control && b.control == c.control &&
                      a.relative == c.relative && b.relative == c.relative;
    if (same && db != 0.0) start = (p_star + (dc / db) * (p_star - shortcut_p_star_)).max(0.0);
  }
  shortcut_p_star_ = std::move(p_star);
  return start;
}

// The shift (m) from the last row to row k's load `target` (its magnitude: a shift, or a force
// converted by the last row's k_x = sum psi h^2, the tangent dF_t/dU): NaN without a tangent.
double Stepper::tangent_shift(int k, double target) const {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  if (shortcut_psi_.size() != state_.pressure.size()) return nan;
  const double U0 = std::abs(model_.tangential_operator->direction().dot(state_.shift));
  if (model_.path.steps.at(std::size_t(k)).control != Control::force) return target - U0;
  std::array<double, 2> sums{state_.traction[0].sum(), shortcut_psi_.sum()};
  model_.half_space->communicator().sum(sums);
  const double area = model_.half_space->grid().cell_area();
  const double kx = sums[1] * area, F0 = std::abs(sums[0]) * area;
  return kx > 0.0 ? (target - F0) / kx : nan;
}

// After row k: its k_x solution when row k + 1 is a shortcut row (the tangent its corrective
// solve starts along), nothing otherwise (no k_x at this row, a reused set).
void Stepper::keep_tangent(std::size_t k, const StepRecord& rec) {
  const Field* psi = model_.stiffness ? model_.stiffness->solution() : nullptr;
  const bool next = k + 1 < steps() && shortcut_applies(k + 1);
  shortcut_psi_ = next && psi && !std::isnan(rec.kx) ? *psi : Field();
}

// K p of the current pressure, the shortcut's p(F_z): one product per normal solution.
const Field& Stepper::pressure_displacement() {
  if (shortcut_pressure_.size() != state_.pressure.size() ||
      !(shortcut_pressure_ == state_.pressure).all()) {
    shortcut_pressure_ = state_.pressure;
    model_.half_space->normal(shortcut_pressure_, shortcut_uz_);
  }
  return shortcut_uz_;
}

// Ciavarella–Jäger superposition instead of an incremental solve (monotone_shortcut.hpp); the
// state, slip and dissipation bookkeeping are those of an incremental step to the same load.
void Stepper::shortcut_step(const LoadStep& ls, StepRecord& rec) {
  TangentialOperator& op = *model_.tangential_operator;
  const Material& mat = model_.scenario.material;
  const Vec2 e = op.direction();
  const double ratio = model_.half_space->tangential_ratio();
  const double scale = ls.relative ? mat.mu * state_.normal_force : 1.0;
  const double target = e.dot(ls.target * (ls.control == Control::force ? scale : 1.0));
  const double sign = target < 0.0 ? -1.0 : 1.0;
  NormalSolver& ns = model_.corrective ? *model_.corrective : *model_.normal;
  const double U0 = std::abs(e.dot(state_.shift));
  const Field p_star0 = shortcut_start(rec.step, std::abs(target));
  const ShortcutResult r =
      ls.control == Control::force
          ? ciavarella_jaeger_force(ns, model_.surface, state_.pressure, state_.normal_force,
                                    state_.indentation, mat.mu, ratio, std::abs(target), &p_star0)
          : ciavarella_jaeger_shift(ns, model_.surface, state_.pressure, state_.indentation, mat.mu,
                                    ratio, std::abs(target), &p_star0);
  const VecField u0 = state_.displacement;
  state_.traction[0] = sign * r.traction;
  // u = C tau = (E*/G*) K mu (p - p*) under the analogy (one kernel, HalfSpace): from the two
  // normal displacements at hand instead of a product.
  state_.displacement[0] = (sign * mat.mu * ratio) * (pressure_displacement() - ns.displacement());
  Eigen::VectorXd dU(1);
  dU(0) = sign * r.shift - e.dot(state_.shift);
  state_.shift += dU(0) * e;
  rec.tangential_iterations = r.corrective.iterations;
  rec.tangential_residual = r.corrective.residual;
  last_target_ = op.to_local(ls.target * (ls.control == Control::force ? scale : 1.0));
  accumulate_slip(u0, nullptr, dU, rec);  // constant normal load: the bound did not move
  kx_start_ = stiffness_start(U0);
}

// The k_x solve's start on a shortcut row: C psi = e_x on the stick set is, under the analogy
// (C = (E*/G*) K), the corrective problem's K psi' = 1 on its contact set with
// psi' = (E*/G*) psi, and dp*/d delta* solves that where the set holds. With
// delta* = delta - U / (mu E*/G*) (eq. 19), psi = -mu dp*/dU, taken along the secant from the
// row before (p*_1, U_1) to this one: exact while the stick set holds.
Field Stepper::secant_stiffness_start(const Field& p_star_before, double U_before) const {
  const double dU = std::abs(model_.tangential_operator->direction().dot(state_.shift)) - U_before;
  if (p_star_before.size() != state_.pressure.size() || !(dU > 0.0)) return Field();
  const double mu = model_.scenario.material.mu;
  const Field p_star = (state_.pressure - state_.traction[0].abs() / mu).max(0.0);
  return (mu / dU) * (p_star_before - p_star);
}

// The secant s is the mean of the tangent psi over the row's interval, the tangent at its
// midpoint where psi varies linearly with U: with the row before's psi_1 (its k_x solution)
// at hand, psi ~ 2 s - psi_1 at this row (exact where psi is linear in U over the two rows;
// the solve restricts it to this row's stick set). Fewer k_x products than from s
// (docs/performance.md, "Paper-ensemble member"). Built from the checkpointed p*_1 and psi_1
// and the state, so a resumed run solves k_x from the start the uninterrupted did.
Field Stepper::stiffness_start(double U_before) const {
  Field start = secant_stiffness_start(shortcut_p_star_, U_before);
  if (start.size() > 0 && shortcut_psi_.size() == start.size()) start = 2.0 * start - shortcut_psi_;
  return start;
}

// Slip increment s = dU - (u - u0) per slip node (stick nodes do not slip: what the solver
// leaves there is its residual); the node states of the step follow from it.
// The work of the step and the wear take one quadrature of the bound along the slip
// (contact/step_work.hpp): exact, g1 |s|, while the bound stays put; second order when it
// moves (a varying normal load: the nodal dissipation converges to the F-U loop area at ~4x
// per halving of the step, test_history_physics).
// Fused passes over the grid (whole-field expressions made seven temporaries: 17 % of a
// full-sliding step of rough_monotone.ini, perf).
void Stepper::accumulate_slip(const VecField& u0, const VecField* tau0, const Eigen::VectorXd& dU,
                              StepRecord&) {
  const int nc = int(state_.traction.size());
  const bool moving = bound_moved_ && tau0 && bound_start_.size() == bound_.size();
  // A contact that does not change (no bound moving within the step, no sub-step estimate that
  // reads the slip off contact): the slip, the states and the booking on the contact nodes
  // only, ~a fifth of the grid in the Mindlin cycle; off contact the nodes stay open and nothing
  // slips (a tenth of a steady cycle's CPU went to these passes over the whole grid, perf).
  const bool listed = contact_fixed_ && !moving && model_.scenario.load.tolerance <= 0.0;
  const std::vector<Eigen::Index>* nodes = listed ? &contact_ : nullptr;
  VecField s;
  step_slip_vectors(u0, dU, s, nodes);  // |s| of the step, before the classification
  const StateField before = moving ? state_.state : StateField();
  const double eps = model_.scenario.solver.tolerance;
  if (listed)
    state_.classify(bound_, eps, work_.slip, slip_threshold(), contact_);
  else
    state_.classify(bound_, eps, work_.slip, slip_threshold());
  if (moving) {
    StepStart start = step_start(before, *tau0);
    const std::optional<StepBefore> prior = step_before();
    if (prior) start.before = &*prior;
    step_work(&start, state_, bound_, s, work_);
  } else if (listed) {
    step_work(state_, bound_, s, work_, contact_);
  } else {
    step_work(nullptr, state_, bound_, s, work_);
  }
  remember_step(moving ? &before : nullptr);
  const auto slip = std::uint8_t(NodeState::slip);
  auto book = [&](Eigen::Index k) {
    const double slipping = state_.state(k) == slip ? 1.0 : 0.0;
    for (int c = 0; c < nc; ++c) state_.slip[c](k) += s[c](k) * slipping;
    state_.slip_path(k) += work_.slip(k) * slipping;
    state_.dissipation(k) += work_.work(k);
  };
  if (listed)
    for (const Eigen::Index k : contact_) book(k);
  else
    for (Eigen::Index k = 0; k < bound_.size(); ++k) book(k);
  if (model_.scenario.load.tolerance > 0.0) estimate_step();
  // The bound the next step starts from is the law's at the history just booked (the settled
  // bound to round-off).
  if (model_.friction->settles_within_step()) model_.friction->bound(state_, bound_);
  const double h2 = model_.half_space->grid().cell_area();
  const Communicator& comm = model_.half_space->communicator();
  dissipation_ += comm.sum(work_.work.sum()) * h2;
  if (!model_.wear) return;  // no wear arithmetic without a wear law
  const Field dh = model_.wear->increment(work_);
  state_.wear += dh;
  wear_volume_ += comm.sum(dh.sum()) * h2;
}

// Slip threshold of the state classification (m): the solver stops when the rms over the N
// contact nodes of the Coulomb-law violation is below tolerance x |C g| (rms over contact), so a
// single node's error can reach sqrt(N) times that; kSlipThreshold is the margin on top.
// |C g| costs one convolution, recomputed only when the bound changed.
double Stepper::slip_threshold() {
  const Communicator& comm = model_.half_space->communicator();
  if (comm.any(!same_bits(scale_bound_, bound_))) {
    scale_bound_ = bound_;
    TangentialOperator& op = *model_.tangential_operator;
    VecField load = op.zeros(), u;
    load[0] = bound_;
    op.apply(load, u);
    const Field contact = (bound_ > 0.0).cast<double>();
    const double n = comm.sum(contact.sum());
    const double scale = n > 0.0 ? std::sqrt(comm.sum((contact * u[0].square()).sum()) / n) : 0.0;
    slip_threshold_ = kSlipThreshold * std::sqrt(n) * model_.scenario.solver.tolerance * scale;
  }
  return slip_threshold_;
}

// This rank's slab of the indenter surface (the whole surface when serial): the surface is
// an input, held whole on every rank like the scenario; the solves take their slab.
const Field& Stepper::local_surface() {
  const HalfSpace& hs = *model_.half_space;
  if (!hs.communicator().distributed()) return model_.surface;
  surface_slab_ = model_.surface.middleCols(hs.first_row(), hs.local_rows());
  return surface_slab_;
}

// The largest height of a surface slab over the ranks (m).
double Stepper::highest(const Field& z) const {
  return model_.half_space->communicator().max(z.maxCoeff());
}

}  // namespace fretbem
