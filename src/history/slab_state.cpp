#include "fretbem/history/slab_state.hpp"

#include <functional>

namespace fretbem {

namespace {

Eigen::Index first_cell(const HalfSpace& hs) {
  return Eigen::Index(hs.first_row()) * hs.grid().nx;
}

StateField gathered_states(const HalfSpace& hs, const StateField& slab) {
  const Field all = gathered(hs, slab.cast<double>());
  return all.cast<std::uint8_t>();
}

// The state with `field` applied to every per-node field and `states` to the node states.
InterfaceState each_field(const InterfaceState& s, const std::function<Field(const Field&)>& field,
                          const std::function<StateField(const StateField&)>& states) {
  const auto each = [&field](const VecField& v) {
    VecField out;
    for (const Field& f : v) out.push_back(field(f));
    return out;
  };
  InterfaceState w = s;
  w.pressure = field(s.pressure);
  w.traction = each(s.traction);
  w.displacement = each(s.displacement);
  w.state = states(s.state);
  w.slip = each(s.slip);
  w.slip_path = field(s.slip_path);
  w.dissipation = field(s.dissipation);
  w.wear = field(s.wear);
  return w;
}

}  // namespace

Field gathered(const HalfSpace& hs, const Field& slab) {
  const Communicator& comm = hs.communicator();
  if (!comm.distributed()) return slab;
  const std::vector<double> all = comm.gather({slab.data(), std::size_t(slab.size())}, 0);
  if (comm.rank() != 0) return {};
  return Eigen::Map<const Field>(all.data(), hs.grid().nx, hs.grid().ny);
}

// Gathered to rank 0, then broadcast: the size is the grid's on every rank.
Field on_every_rank(const HalfSpace& hs, const Field& slab) {
  const Communicator& comm = hs.communicator();
  if (!comm.distributed()) return slab;
  Field whole = gathered(hs, slab);
  whole.resize(hs.grid().nx, hs.grid().ny);
  comm.broadcast({whole.data(), std::size_t(whole.size())}, 0);
  return whole;
}

Field slab_of(const HalfSpace& hs, const Field& whole) {
  if (!hs.communicator().distributed() || whole.size() == 0) return whole;
  return whole.middleCols(hs.first_row(), hs.local_rows());
}

InterfaceState gathered(const HalfSpace& hs, const InterfaceState& s) {
  if (!hs.communicator().distributed()) return s;
  return each_field(
      s, [&hs](const Field& f) { return gathered(hs, f); },
      [&hs](const StateField& f) { return gathered_states(hs, f); });
}

InterfaceState slab_of(const HalfSpace& hs, const InterfaceState& s) {
  if (!hs.communicator().distributed()) return s;
  return each_field(
      s, [&hs](const Field& f) { return slab_of(hs, f); },
      [&hs](const StateField& f) -> StateField {
        return f.middleCols(hs.first_row(), hs.local_rows());
      });
}

StepperMemory gathered(const HalfSpace& hs, const StepperMemory& m) {
  const Communicator& comm = hs.communicator();
  if (!comm.distributed()) return m;
  StepperMemory w = m;
  for (auto& [name, f] : w.fields) f = gathered(hs, f);  // the same names on every rank
  w.masing = MasingImage::gathered(m.masing, comm, first_cell(hs));
  return w;
}

StepperMemory slab_of(const HalfSpace& hs, const StepperMemory& m) {
  if (!hs.communicator().distributed()) return m;
  StepperMemory w = m;
  for (auto& [name, f] : w.fields) f = slab_of(hs, f);
  w.masing =
      MasingImage::sliced(m.masing, first_cell(hs), Eigen::Index(hs.local_rows()) * hs.grid().nx);
  return w;
}

}  // namespace fretbem
