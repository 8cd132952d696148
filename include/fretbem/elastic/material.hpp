// Material: the effective elastic constants of the contact pair (README, "Conventions and physics").
#pragma once

#include <optional>

namespace fretbem {

/// One isotropic linear-elastic body: Young's modulus E (Pa) and Poisson's ratio nu (-).
struct Body {
  double E = 0.0;
  double nu = 0.0;
  double G() const { return E / (2.0 * (1.0 + nu)); }
};

/// The elastic pair: body 1 is the half-space; body 2 (optional) is the indenter's material.
/// With no body 2 the indenter is rigid.
struct Material {
  Body body1;
  std::optional<Body> body2;
  double mu = 0.3;  ///< Coulomb friction coefficient (-)

  /// 1/E* = (1-nu1^2)/E1 + (1-nu2^2)/E2 (Pa).
  double E_star() const;
  /// 1/G* = (2-nu1)/(4 G1) + (2-nu2)/(4 G2) (Pa): Cattaneo–Mindlin tangential modulus.
  double G_star() const;
  /// Cerruti compliance weights of the pair, summed over bodies (1/Pa):
  /// a = sum (1-nu_k)/(2 pi G_k), b = sum nu_k/(2 pi G_k). Point-force displacement
  /// u_x = Q [a / r + b x^2 / r^3], u_y = Q b x y / r^3 (Johnson, Contact Mechanics, eq. 3.86a).
  double cerruti_a() const;
  double cerruti_b() const;
  /// Normal-tangential cross compliance of the pair (1/Pa), body 1 minus body 2:
  /// c = (1-2 nu1)/(4 pi G1) - (1-2 nu2)/(4 pi G2). A compressive point force P moves the
  /// surfaces relative to each other by -c P r/r^2 (Boussinesq, Johnson eq. 3.19a: each surface
  /// is drawn towards the load); a tangential point force Q on body 1 (-Q on body 2) changes the
  /// normal approach by c Q.r/r^2 (Cerruti, eq. 3.86c, by reciprocity). Exactly 0 for identical
  /// bodies; c = beta / (pi E*).
  double cross_compliance() const;
  /// Dundurs' second constant, beta = pi E* c (Johnson eq. 5.4 with body 1 the half-space):
  /// (1-2 nu)/(2 (1-nu)) for a rigid indenter, 0 for identical or incompressible bodies;
  /// exchanging the bodies flips its sign.
  double dundurs_beta() const;
};

}  // namespace fretbem
