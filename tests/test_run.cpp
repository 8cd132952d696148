// The run layer (run/) in process: a run stopped and resumed through run_scenario and
// resume_run writes the uninterrupted run's rows, and one Observer receives a run's steps and
// its wear events alike.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "fretbem/history/model.hpp"
#include "fretbem/history/observer.hpp"
#include "fretbem/history/stepper.hpp"
#include "fretbem/run/run.hpp"
#include "fretbem/scenario/scenario.hpp"
#include "fretbem/wear/integrator.hpp"
#include "support/csv_text.hpp"
#include "support/temp_dir.hpp"

namespace fs = std::filesystem;
using namespace fretbem;

namespace {

fs::path fresh_dir(const std::string& name) {
  return fretbem_test::process_temp_dir().vacant(name);
}

// The Mindlin–Deresiewicz loop of mindlin_cycle.ini at n = 32, two cycles of 16 steps.
Scenario mindlin(const fs::path& out, std::vector<std::string> sets = {}) {
  sets.insert(sets.end(), {"grid.n=32", "load.cycles=2", "load.steps_per_cycle=16"});
  Scenario sc =
      load_scenario(fs::path(FRETBEM_SOURCE_DIR) / "scenarios" / "mindlin_cycle.ini", sets);
  set_output_dir(sc, out);
  return sc;
}

}  // namespace

// Stopped after 5 steps, then resumed: timeseries.csv and cycles.csv are the uninterrupted
// run's, byte for byte (the same arithmetic from the checkpointed state), but for the work
// counter `convolutions` and without kx: the stiffness CG's warm start is not checkpointed, so
// kx agrees only to its solver tolerance (tests/test_faults.cpp).
TEST(RunLayer, StoppedAndResumedRunWritesTheUninterruptedRows) {
  const fs::path full = fresh_dir("full"), part = fresh_dir("part");
  const std::vector<std::string> no_kx{"solver.stiffness=none"};
  ASSERT_EQ(run_scenario(mindlin(full, no_kx), {.quiet = true}), 0);
  ASSERT_EQ(run_scenario(mindlin(part, no_kx), {.quiet = true, .stop_after = 5}), 0);
  EXPECT_TRUE(fs::exists(part / "checkpoint.h5"));
  ASSERT_EQ(resume_run(part, {.quiet = true}), 0);
  EXPECT_EQ(fretbem_test::differing_tables(full, part, "convolutions"), "");
  fs::remove_all(full);
  fs::remove_all(part);
}

// A path of step 0 alone (normal loading only) is finished by its first step: the observers
// are told once, and a --overwrite run drops the results it replaced (it has finished).
TEST(RunLayer, NormalOnlyRunFinishesOnceAndReplacesTheOldResults) {
  const fs::path dir = fresh_dir("normal");
  ASSERT_EQ(run_scenario(mindlin(dir, {"load.path=none"}), {.quiet = true}), 0);
  ASSERT_EQ(run_scenario(mindlin(dir, {"load.path=none"}), {.quiet = true, .overwrite = true}), 0);
  EXPECT_FALSE(fs::exists(dir / ".fretbem-replaced"));
  EXPECT_FALSE(fs::exists(dir / ".fretbem-replacing"));
  std::ifstream ts(dir / "timeseries.csv");
  std::string line;
  int lines = 0;
  while (std::getline(ts, line)) ++lines;
  EXPECT_EQ(lines, 2);  // the header and row 0
  fs::remove_all(dir);
}

namespace {

// Every event of a wear run, through the one interface.
struct Events final : Observer {
  std::vector<StepRecord> rows;
  std::vector<WearCycle> cycles;
  std::vector<double> dissipation_at_cycle_end;  // of the last row before each cycle event
  int checkpoints = 0;
  void on_step(const StepRecord& r, const InterfaceState&, const Model&) override {
    rows.push_back(r);
  }
  void cycle(const WearCycle& c) override {
    cycles.push_back(c);
    dissipation_at_cycle_end.push_back(rows.back().dissipation);
  }
  void step_done(const WearCheckpoint&) override { ++checkpoints; }
};

}  // namespace

// Cycle mode over 4 cycles: the observer sees row 0 and the rows of N + 1 simulated cycles,
// one cycle event per cycle, a finished wear step after each but the last (which observes
// the final surface and ends the run), and each cycle's energy is the growth
// of the rows' cumulative dissipation over that cycle (an identity between the two event
// streams).
TEST(RunLayer, OneObserverSeesAWearRunsStepsAndCycles) {
  Scenario sc = load_scenario(fs::path(FRETBEM_SOURCE_DIR) / "scenarios" / "fretting_wear.ini",
                              {"grid.n=32", "wear.integrator=cycle", "wear.cycles=4"});
  set_output_dir(sc, fresh_dir("events"));
  auto model = build_model(sc);
  Stepper stepper(*model);
  Events events;
  WearCycles sim(*model, stepper, {&events});
  const WearReport rep = integrate_wear(*model, sim, events);
  ASSERT_EQ(events.cycles.size(), 5u);  // N = 0..4
  EXPECT_EQ(events.checkpoints, 4);
  EXPECT_EQ(int(events.rows.size()), sim.counters().rows);
  EXPECT_EQ(events.rows.front().step, 0);
  double before = events.rows.front().dissipation;
  for (std::size_t k = 0; k < events.cycles.size(); ++k) {
    EXPECT_EQ(events.cycles[k].N, double(k));
    EXPECT_GT(events.cycles[k].energy, 0.0);
    EXPECT_DOUBLE_EQ(events.cycles[k].energy, events.dissipation_at_cycle_end[k] - before);
    before = events.dissipation_at_cycle_end[k];
  }
  EXPECT_EQ(rep.history.size(), events.cycles.size());
}
