#include "fretbem/elastic/material.hpp"

#include <numbers>

namespace fretbem {

namespace {
double normal_compliance(const Body& b) {
  return (1.0 - b.nu * b.nu) / b.E;
}
double tangential_compliance(const Body& b) {
  return (2.0 - b.nu) / (4.0 * b.G());
}
}  // namespace

double Material::E_star() const {
  double c = normal_compliance(body1);
  if (body2) c += normal_compliance(*body2);
  return 1.0 / c;
}

double Material::G_star() const {
  double c = tangential_compliance(body1);
  if (body2) c += tangential_compliance(*body2);
  return 1.0 / c;
}

double Material::cerruti_a() const {
  const double pi = std::numbers::pi;
  double a = (1.0 - body1.nu) / (2.0 * pi * body1.G());
  if (body2) a += (1.0 - body2->nu) / (2.0 * pi * body2->G());
  return a;
}

double Material::cerruti_b() const {
  const double pi = std::numbers::pi;
  double b = body1.nu / (2.0 * pi * body1.G());
  if (body2) b += body2->nu / (2.0 * pi * body2->G());
  return b;
}

double Material::cross_compliance() const {
  const double pi = std::numbers::pi;
  auto part = [pi](const Body& b) { return (1.0 - 2.0 * b.nu) / (4.0 * pi * b.G()); };
  return body2 ? part(body1) - part(*body2) : part(body1);
}

double Material::dundurs_beta() const {
  return std::numbers::pi * E_star() * cross_compliance();
}

}  // namespace fretbem
