#include "fretbem/run/run.hpp"

#include <cstdio>
#include <optional>
#include <system_error>

#include "fretbem/core/errors.hpp"
#include "fretbem/core/output_lock.hpp"
#include "fretbem/core/rank_zero.hpp"
#include "fretbem/history/model.hpp"
#include "fretbem/history/slab_state.hpp"
#include "fretbem/io/checkpoint.hpp"
#include "fretbem/io/replaced_results.hpp"
#include "fretbem/io/result_recovery.hpp"
#include "fretbem/io/resume_check.hpp"
#include "fretbem/run/replacement_end.hpp"
#include "fretbem/run/stepped_run.hpp"
#include "fretbem/run/wear_run.hpp"

namespace fretbem {

namespace {

RunEnd wear_end(const WearReport& rep) {
  return {.code = rep.exit_code, .finished = !rep.stopped};
}

RunEnd steps_end(int code, const Stepper& stepper) {
  return {.code = code, .finished = stepper.next_step() >= stepper.steps()};
}

void warn_if_any(const std::string& warning) {
  if (!warning.empty()) std::fprintf(stderr, "fretbem: %s\n", warning.c_str());
}

// A wear run's checkpoint: its rows, fields and snapshots are checked and result.h5 rebuilt
// to them (by rank 0 of a distributed grid), then the wear integration continues.
RunEnd resume_wear(Model& model, const Checkpoint& cp, const std::filesystem::path& dir,
                   const RunOptions& options) {
  if (!cp.wear) throw InputError((dir / "checkpoint.h5").string() + ": not a wear run's");
  on_rank_zero(model.half_space->communicator(), [&] {
    check_finished_rows(dir / "timeseries.csv", std::size_t(cp.wear->counters.rows));
    check_finished_rows(dir / "cycles.csv", std::size_t(cp.wear->cycles_rows));
    warn_if_any(prepare_result_for_resume(
        dir, model, cp.run_id,
        {.rows = std::size_t(cp.wear->counters.rows),
         .field_steps = std::int64_t(cp.wear->counters.rows),  // fields are of rows
         .snapshots = cp.wear->snapshots}));
  });
  return wear_end(run_wear(model, options.quiet, &cp, options.stop_after));
}

// A stepped run's checkpoint: result.h5 is never written in place (a kill may have torn it,
// result_recovery.hpp); the stepper continues from the restored state and predictor.
// On a distributed grid each rank takes its slab of the whole grid's checkpoint.
RunEnd resume_steps(Model& model, const Checkpoint& cp, const std::filesystem::path& dir,
                    const RunOptions& options) {
  if (cp.wear)
    throw InputError((dir / "checkpoint.h5").string() + ": a wear run's, but no wear.law");
  const auto done = std::int64_t(cp.memory.next_step);
  const HalfSpace& hs = *model.half_space;
  on_rank_zero(hs.communicator(), [&] {
    check_finished_rows(dir / "timeseries.csv", cp.memory.next_step);
    warn_if_any(prepare_result_for_resume(dir, model, cp.run_id,
                                          {.rows = cp.memory.next_step, .field_steps = done}));
  });
  model.surface = cp.surface;
  Stepper stepper(model);
  const Eigen::Index first = Eigen::Index(hs.first_row()) * hs.grid().nx,
                     cells = Eigen::Index(hs.local_rows()) * hs.grid().nx;
  const std::vector<double>& predictor = hs.communicator().distributed()
                                             ? CyclePredictor::sliced(cp.predictor, first, cells)
                                             : cp.predictor;
  stepper.restore(slab_of(hs, cp.state), slab_of(hs, cp.memory),
                  CyclePredictor::unflatten(predictor, std::size_t(cells),
                                            model.tangential_operator->components()));
  return steps_end(run_steps(model, stepper, long(cp.memory.next_step), options), stepper);
}

}  // namespace

// On a grid distributed over ranks every rank builds the model (the same inputs, refused
// alike) and rank 0 alone takes the folder: its lock, the results set aside, the files.
int run_scenario(const Scenario& scenario, const RunOptions& options, const Communicator& comm) {
  auto model = build_model(scenario, comm);
  const auto& dir = scenario.output.dir;
  std::optional<OutputLock> lock;
  on_rank_zero(comm, [&] {
    lock.emplace(dir);  // before the checks: no second run slips in between
    warn_if_any(settle_replaced_results(dir));
    prepare_output_dir(dir, options.overwrite);
  });
  model->run_id = new_run_id();
  return settle_replacement_at_end(dir, comm, [&] {
    if (model->wear) return wear_end(run_wear(*model, options.quiet, nullptr, options.stop_after));
    Stepper stepper(*model);
    return steps_end(run_steps(*model, stepper, -1, options), stepper);
  });
}

// Every rank reads the checkpoint (after rank 0 has settled the folder) and takes its slab.
// A resume that fails, refused checkpoint included, puts back the results its run replaces.
int resume_run(const std::filesystem::path& dir, const RunOptions& options,
               const Communicator& comm) {
  std::optional<OutputLock> lock;
  on_rank_zero(comm, [&] {
    std::error_code ec;
    if (!std::filesystem::is_directory(dir, ec))
      throw InputError(dir.string() + ": not a folder of a run to resume");
    lock.emplace(dir);
    warn_if_any(settle_replaced_results(dir));
    check_output_files(dir);
  });
  return settle_replacement_at_end(dir, comm, [&] {
    const Checkpoint cp = load_checkpoint(dir);
    Scenario sc = parse_scenario(cp.scenario_text, (dir / "checkpoint.h5").string(), ".", {});
    set_output_dir(sc, dir);
    auto model = build_model(sc, comm);
    validate_checkpoint(cp, *model, dir / "checkpoint.h5");
    model->run_id = cp.run_id;
    return model->wear ? resume_wear(*model, cp, dir, options)
                       : resume_steps(*model, cp, dir, options);
  });
}

}  // namespace fretbem
