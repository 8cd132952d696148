#include "fretbem/io/wear_files.hpp"

#include <cmath>
#include <cstdio>

#include "fretbem/core/format.hpp"
#include "fretbem/core/rank_zero.hpp"
#include "fretbem/core/stop_signal.hpp"
#include "fretbem/history/slab_state.hpp"
#include "fretbem/io/checkpoint.hpp"

namespace fretbem {

namespace {

// DIR/cycles.csv of a wear run: one row per simulated cycle, then the bookkeeping
// columns; the per-body volumes split wear_volume by wear.indenter_share.
const std::vector<std::string>& wear_columns() {
  static const std::vector<std::string> c{"N",
                                          "energy_per_cycle",
                                          "wear_volume",
                                          "max_worn_depth",
                                          "contact_radius",
                                          "stick_area",
                                          "peak_pressure",
                                          "delta",
                                          "max_slip",
                                          "simulated_cycles",
                                          "accepted",
                                          "wear_volume_indenter",
                                          "wear_volume_half_space"};
  return c;
}

}  // namespace

// Simulated cycles are sums of fractions of a period (a steady cycle counts 1.2 at one step
// per ramp step), and an ODE run's N is real: printed to 1e-6 cycles so round-off
// ("67.80000000000007", "N = 8801.740264644288") does not show; whole counts as integers.
std::string simulated_count(double simulated) {
  return format_count(std::round(simulated * 1e6) / 1e6);
}

WearFiles::WearFiles(const Model& model, const Stepper& stepper, ResultFile* h5, bool quiet,
                     const WearCheckpoint* resume)
    : model_(model),
      stepper_(stepper),
      h5_(h5),
      progress_(!quiet && model.half_space->communicator().rank() == 0) {
  on_rank_zero(comm(), [&] {
    csv_.emplace(open_csv(model.scenario.output.dir, "cycles", wear_columns(),
                          resume ? resume->cycles_rows : -1));
  });
  if (resume) rows_ = resume->cycles_rows, snapshots_ = resume->snapshots;
}

// A signal may reach the ranks at different times: all stop after the wear step in which one
// saw it.
bool WearFiles::stop_requested() const {
  return comm().any(fretbem::stop_requested());
}

void WearFiles::cycle(const WearCycle& c) {
  ++rows_;
  on_rank_zero(comm(), [&] {
    const double s = model_.scenario.wear.indenter_share;
    // N is the count a cycle stands for: integral in cycle mode and stretches (summed ones),
    // where round-off must not print 2.9999999999999996 (format_count).
    csv_->row({snap_count(c.N), c.energy, c.wear_volume, c.max_depth, c.contact_radius,
               c.stick_area, c.peak_pressure, c.delta, c.max_slip, c.simulated,
               c.accepted ? 1.0 : 0.0, s * c.wear_volume, (1.0 - s) * c.wear_volume});
    if (c.accepted) last_accepted_ = {snap_count(c.N), c.energy};
    progress(c.N, c.simulated);
  });
}

// The total worn depth (what the gap sees) and each body's share of it; and, at the end of
// a simulated cycle, the fields asked of that state.
void WearFiles::snapshot(double N, const Field& worn_slab, const Field& p_slab, bool cycle_end) {
  const HalfSpace& hs = *model_.half_space;
  const Field worn = gathered(hs, worn_slab), p = gathered(hs, p_slab);
  const InterfaceState state = cycle_end ? gathered(hs, stepper_.state()) : InterfaceState();
  const std::int64_t group = snapshots_++;
  on_rank_zero(comm(), [&] {
    if (cycle_end) h5_->save_fields(state, model_);
    h5_->writer().write_step_fields(group, N,
                                    {{"worn_depth", worn},
                                     {"worn_depth_indenter", indenter_worn(model_, worn)},
                                     {"worn_depth_half_space", half_space_worn(model_, worn)},
                                     {"pressure", p}},
                                    "/wear/snapshot_");
  });
}

// The checkpoint holds the whole grid's fields (save_checkpoint gathers the state's).
void WearFiles::step_done(const WearCheckpoint& at) {
  const HalfSpace& hs = *model_.half_space;
  WearCheckpoint c = at;
  // One rank holds the whole grid already: gathering would copy every field once more (the
  // warm start's path alone is up to 8 grid fields).
  if (hs.communicator().distributed()) {
    c.worn = gathered(hs, at.worn);
    // A warm start is empty (cold) on every rank alike.
    c.warm = at.warm.mapped([&](const Field& x) { return gathered(hs, x); });
  }
  c.cycles_rows = rows_, c.snapshots = snapshots_;
  save_checkpoint(model_.scenario.output.dir, model_, stepper_, &c);
}

// On stderr, with --quiet too: it says what the run will cost before it is spent.
void WearFiles::warn(const std::string& line) {
  if (comm().rank() != 0) return;
  progress_.finish();
  std::fprintf(stderr, "fretbem: %s\n", line.c_str());
}

// The ETA counts on the simulated cycles, which carry the cost (one steady cycle each), not
// on N: an ODE integrator's steps lengthen with N, so N / wear.cycles overstates the time
// left by orders of magnitude early on (fretting_wear.ini at n = 64: 83 s at 1 s for 3.4 s
// left). The expected range's middle first, then its upper end, then N once the run exceeds
// both (its cost is then unknown).
double WearFiles::done_share(double N, double simulated) const {
  if (simulated < expected_.middle()) return simulated / expected_.middle();
  if (simulated < expected_.high) return simulated / expected_.high;
  return N / model_.scenario.wear.cycles;
}

void WearFiles::progress(double N, double simulated) {
  const double total = model_.scenario.wear.cycles;
  progress_.update("wear: N " + format_count(N) + " / " + format_count(total) +
                       "  simulated cycles " + simulated_count(simulated),
                   done_share(N, simulated));
}

}  // namespace fretbem
