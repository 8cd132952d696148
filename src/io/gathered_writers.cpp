#include "fretbem/io/gathered_writers.hpp"

#include "fretbem/core/rank_zero.hpp"
#include "fretbem/history/model.hpp"
#include "fretbem/history/slab_state.hpp"
#include "fretbem/io/run_output.hpp"

namespace fretbem {

void GatheredWriters::on_step(const StepRecord& rec, const InterfaceState& state,
                              const Model& model) {
  // Only the saved fields read the state (the rows are in `rec`): gathering the whole grid at
  // every step would put output work on the stepping path. The decision is the same on every
  // rank (it reads only the record and the scenario), so all enter the gather or none does.
  const InterfaceState whole =
      fields_saved_at(rec, model) ? gathered(*model.half_space, state) : InterfaceState();
  on_rank_zero(model.half_space->communicator(), [&] {
    for (Observer* o : writers_) o->on_step(rec, whole, model);
  });
}

void GatheredWriters::on_finish(const InterfaceState& state, const Model& model) {
  const InterfaceState whole = gathered(*model.half_space, state);
  on_rank_zero(model.half_space->communicator(), [&] {
    for (Observer* o : writers_) o->on_finish(whole, model);
  });
}

}  // namespace fretbem
