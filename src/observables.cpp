#include "fretbem/observables.hpp"

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
                                          "convolutions"};
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
          double(convolutions)};
}

void measure_areas(const InterfaceState& s, const TangentialOperator& op, StepRecord& r) {
  const double a = op.grid().cell_area();
  const auto stick = (s.state == std::uint8_t(NodeState::stick));
  const auto slip = (s.state == std::uint8_t(NodeState::slip));
  r.stick_area = stick.count() * a;
  r.slip_area = slip.count() * a;
  r.contact_area = r.stick_area + r.slip_area;
  // x component of the traction in global axes.
  const double ex = op.components() == 1 ? op.direction().x() : 1.0;
  r.Fx_stick = (stick.cast<double>() * s.traction[0]).sum() * ex * a;
}

}  // namespace fretbem
