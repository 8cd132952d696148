#include "fretbem/io/gathered_writers.hpp"

#include "fretbem/core/rank_zero.hpp"
#include "fretbem/history/model.hpp"
#include "fretbem/history/slab_state.hpp"

namespace fretbem {

void GatheredWriters::on_step(const StepRecord& rec, const InterfaceState& state,
                              const Model& model) {
  const InterfaceState whole = gathered(*model.half_space, state);
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
