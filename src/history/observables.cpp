#include "fretbem/history/observables.hpp"

#include <array>

#include "fretbem/history/resolution.hpp"
#include "fretbem/history/slab_measures.hpp"

namespace fretbem {

const std::vector<std::string>& StepRecord::columns() {
  static const std::vector<std::string> c{"step",
                                          "time",
                                          "cycle",
                                          "Fz",
                                          "delta",
                                          "Fx",
                                          "Fy",
                                          "Ux",
                                          "Uy",
                                          "contact_area",
                                          "stick_area",
                                          "slip_area",
                                          "Fx_stick",
                                          "kx",
                                          "dissipation",
                                          "wear_volume",
                                          "normal_iterations",
                                          "tangential_iterations",
                                          "normal_residual",
                                          "tangential_residual",
                                          "convolutions",
                                          "turning",
                                          "stuck_at_bound_area",
                                          "slip_ring_cells",
                                          "contact_nodes",
                                          "edge_load_share",
                                          "coupling_iterations",
                                          "coupling_residual",
                                          "step_error"};
  return c;
}

std::vector<double> StepRecord::values() const {
  return {double(step),
          time,
          double(cycle),
          Fz,
          delta,
          Fx,
          Fy,
          Ux,
          Uy,
          contact_area,
          stick_area,
          slip_area,
          Fx_stick,
          kx,
          dissipation,
          wear_volume,
          double(normal_iterations),
          double(tangential_iterations),
          normal_residual,
          tangential_residual,
          double(convolutions),
          turning ? 1.0 : 0.0,
          stuck_at_bound_area,
          slip_ring_cells,
          double(contact_nodes),
          edge_load_share,
          double(coupling_iterations),
          coupling_residual,
          step_error};
}

StepRecord StepRecord::from_values(const std::vector<double>& v) {
  StepRecord r;
  if (v.size() < 22) return r;  // the 22 columns every version wrote; later ones may be absent
  r.step = int(v[0]), r.time = v[1], r.cycle = int(v[2]);
  r.Fz = v[3], r.delta = v[4], r.Fx = v[5], r.Fy = v[6], r.Ux = v[7], r.Uy = v[8];
  r.contact_area = v[9], r.stick_area = v[10], r.slip_area = v[11], r.Fx_stick = v[12];
  r.kx = v[13], r.dissipation = v[14], r.wear_volume = v[15];
  r.normal_iterations = int(v[16]), r.tangential_iterations = int(v[17]);
  r.normal_residual = v[18], r.tangential_residual = v[19], r.convolutions = int(v[20]);
  r.turning = v[21] != 0.0;
  if (v.size() > 22) r.stuck_at_bound_area = v[22];
  if (v.size() > 25)
    r.slip_ring_cells = v[23], r.contact_nodes = long(v[24]), r.edge_load_share = v[25];
  if (v.size() > 27) r.coupling_iterations = int(v[26]), r.coupling_residual = v[27];
  if (v.size() > 28) r.step_error = v[28];
  return r;
}

// One pass over the states (five whole-grid masks and counts before: 5 % of a full-sliding
// step, perf). F_x of the stick part sums in index order, where Eigen's sum of the masked
// field did not: the column can move in its last bits. A fixed contact's list is in index
// order too and skips only open nodes, which add nothing: the same sums.
void measure_areas(const InterfaceState& s, const TangentialOperator& op, const HalfSpace& hs,
                   StepRecord& r, const FixedContact* fixed) {
  const double a = op.grid().cell_area();
  std::int64_t stick = 0, at_bound = 0, slip = 0;
  double fstick = 0.0;
  auto count = [&](Eigen::Index k) {
    const auto st = NodeState(s.state(k));
    if (st == NodeState::slip) ++slip;
    if (st != NodeState::stick && st != NodeState::stuck_at_bound) return;
    ++stick, at_bound += st == NodeState::stuck_at_bound;
    fstick += s.traction[0](k);
  };
  if (fixed)
    for (const Eigen::Index k : fixed->nodes) count(k);
  else
    for (Eigen::Index k = 0; k < s.state.size(); ++k) count(k);
  // The counts and the stick force of every rank of a distributed grid (serial: as they are).
  std::array<double, 5> totals{double(stick), double(at_bound), double(slip), fstick,
                               fixed ? double(fixed->nodes.size()) : 0.0};
  hs.communicator().sum(totals);
  // Stick: did not slip in this step, inside the bound or on it.
  r.stick_area = totals[0] * a;
  r.stuck_at_bound_area = totals[1] * a;
  r.slip_ring_cells =
      fixed ? slip_ring_width(long(totals[2]), fixed->edges) : slip_ring_cells(s.state, hs);
  r.contact_nodes = fixed ? long(totals[4]) : contact_nodes(s.state, hs);
  r.slip_area = totals[2] * a;
  fstick = totals[3];
  r.contact_area = r.stick_area + r.slip_area;
  // x component of the traction in global axes.
  const double ex = op.components() == 1 ? op.direction().x() : 1.0;
  r.Fx_stick = fstick * ex * a;
}

}  // namespace fretbem
