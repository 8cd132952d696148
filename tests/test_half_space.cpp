// Validation rung 1 (docs/architecture.md, "Validation ladder"): Love's cell coefficients and the
// FFT half-space operator.
//
// References used here are independent of src/elastic/love.cpp: 2-D numerical quadrature of the
// point-force Green's functions over a cell, direct O(n^4) summation, the point-force limits
// of Boussinesq and Cerruti (Johnson, Contact Mechanics, eqs. 3.19a and 3.86a), and the
// lattice sum of the periodic images.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <numbers>
#include <random>
#include <vector>

#include "fretbem/elastic/grid.hpp"
#include "fretbem/elastic/half_space.hpp"
#include "fretbem/elastic/kernel_samples.hpp"
#include "fretbem/elastic/love.hpp"
#include "fretbem/elastic/material.hpp"

namespace fretbem {
namespace {

constexpr double pi = std::numbers::pi;
constexpr double eps = std::numeric_limits<double>::epsilon();

// ---------------------------------------------------------------------------------------------
// Quadrature
// ---------------------------------------------------------------------------------------------

// Gauss–Legendre nodes and weights on [0, 1], by Newton iteration on P_n.
struct GaussLegendre {
  std::vector<double> x, w;
  explicit GaussLegendre(int n) : x(n), w(n) {
    for (int i = 0; i < n; ++i) {
      double z = std::cos(pi * (i + 0.75) / (n + 0.5)), dp = 0.0;
      for (int it = 0; it < 100; ++it) {
        double p0 = 1.0, p1 = z;
        for (int k = 2; k <= n; ++k) {
          const double p2 = ((2.0 * k - 1.0) * z * p1 - (k - 1.0) * p0) / k;
          p0 = p1, p1 = p2;
        }
        dp = n * (z * p1 - p0) / (z * z - 1.0);
        const double dz = p1 / dp;
        z -= dz;
        if (std::fabs(dz) < 1e-16) break;
      }
      x[i] = 0.5 * (1.0 - z);
      w[i] = 1.0 / ((1.0 - z * z) * dp * dp);  // = 2/((1-z^2) P'^2), halved for [0, 1]
    }
  }
};

const GaussLegendre& gl20() {
  static const GaussLegendre g(20);
  return g;
}

using Kernel2 = std::function<double(double, double)>;

// Adaptive Gauss–Legendre of a 1-D function on [t0, t1]: bisect until the 20-point rule on the
// whole interval and on its halves agree to `tol` (absolute). The depth cap keeps a tolerance
// below round-off from recursing forever; 2^16 panels is far more than any integrand here needs.
double adaptive(const std::function<double(double)>& f, double t0, double t1, double tol,
                int depth = 0) {
  const auto& g = gl20();
  auto rule = [&](double a, double b) {
    double s = 0.0;
    for (std::size_t k = 0; k < g.x.size(); ++k) s += g.w[k] * f(a + (b - a) * g.x[k]);
    return s * (b - a);
  };
  const double m = 0.5 * (t0 + t1);
  const double whole = rule(t0, t1), halves = rule(t0, m) + rule(m, t1);
  if (std::fabs(whole - halves) <= tol || depth >= 16) return halves;
  return adaptive(f, t0, m, 0.5 * tol, depth + 1) + adaptive(f, m, t1, 0.5 * tol, depth + 1);
}

// Integral of f(X, Y) over the cell |x'| <= a, |y'| <= b, with X = x - x', Y = y - y': the
// rectangle [x-a, x+a] x [y-b, y+b] in (X, Y), whose integrand is singular like 1/r at the
// origin. The rectangle is the signed fan of triangles (origin, P_k, P_k+1) over its edges,
// which holds wherever the origin is (inside, outside, on an edge line). On each triangle
// (s, t) -> s P(t) maps the unit square with Jacobian s |P_k x P_k+1|; for f homogeneous of
// degree -1 (all kernels here) s f(s P) = f(P) is bounded, so the singularity is gone.
// Triangles with the origin on their edge line have zero area and are skipped.
double cell_quadrature(const Kernel2& f, double x, double y, double a, double b) {
  const double px[4] = {x - a, x + a, x + a, x - a}, py[4] = {y - b, y - b, y + b, y + b};
  const double scale = std::max({std::fabs(x) + a, std::fabs(y) + b});
  const auto& g = gl20();
  double sum = 0.0;
  for (int k = 0; k < 4; ++k) {
    const double x0 = px[k], y0 = py[k], x1 = px[(k + 1) % 4], y1 = py[(k + 1) % 4];
    const double cross = x0 * y1 - x1 * y0;
    if (std::fabs(cross) <= 1e-14 * scale * scale) continue;
    auto edge = [&](double t) {
      const double X = x0 + t * (x1 - x0), Y = y0 + t * (y1 - y0);
      double s = 0.0;
      for (std::size_t q = 0; q < g.x.size(); ++q) s += g.w[q] * g.x[q] * f(g.x[q] * X, g.x[q] * Y);
      return s;
    };
    // Target 1e-15 of the edge's own integral (bounded below by round-off of the sum).
    const double rough = std::fabs(adaptive(edge, 0.0, 1.0, 1e300));
    sum += cross * adaptive(edge, 0.0, 1.0, 1e-15 * rough + 1e-300);
  }
  return sum;
}

// Plain tensor-product Gauss–Legendre over the cell (4 x 4 panels of 20 x 20 points): valid
// only away from the cell, where the integrand is smooth. A second, unrelated reference for the
// far field.
double cell_tensor_quadrature(const Kernel2& f, double x, double y, double a, double b) {
  const auto& g = gl20();
  constexpr int panels = 4;
  double sum = 0.0;
  for (int pi_ = 0; pi_ < panels; ++pi_)
    for (int pj = 0; pj < panels; ++pj)
      for (std::size_t i = 0; i < g.x.size(); ++i)
        for (std::size_t j = 0; j < g.x.size(); ++j) {
          const double xs = -a + 2 * a * (pi_ + g.x[i]) / panels;
          const double ys = -b + 2 * b * (pj + g.x[j]) / panels;
          sum += g.w[i] * g.w[j] * f(x - xs, y - ys);
        }
  return sum * (2 * a / panels) * (2 * b / panels);
}

double inv_r(double X, double Y) {
  return 1.0 / std::hypot(X, Y);
}
double xx_r3(double X, double Y) {
  const double r = std::hypot(X, Y);
  return X * X / (r * r * r);
}
double yy_r3(double X, double Y) {
  const double r = std::hypot(X, Y);
  return Y * Y / (r * r * r);
}
double xy_r3(double X, double Y) {
  const double r = std::hypot(X, Y);
  return X * Y / (r * r * r);
}

// Love's corner sum with the *wrong* antiderivative X asinh(Y/X) + Y asinh(X/Y) (no absolute
// values): used only to show that the test points below can tell the two forms apart.
double I1_without_abs(double x, double y, double a, double b) {
  auto F = [](double X, double Y) {
    return (X == 0 ? 0.0 : X * std::asinh(Y / X)) + (Y == 0 ? 0.0 : Y * std::asinh(X / Y));
  };
  return F(x + a, y + b) - F(x + a, y - b) - F(x - a, y + b) + F(x - a, y - b);
}

// Field points for a cell of half-sides a = 0.5, b = 0.8 (non-square on purpose).
struct Point {
  double x, y;
  bool mixed;  // some corner offset pair x±a or y±b has mixed signs
};
constexpr double A = 0.5, B = 0.8;
const std::vector<Point>& test_points() {
  static const std::vector<Point> pts = {
      {0.0, 0.0, true},            // own centre
      {0.3 * A, -0.7 * B, true},   // inside, off centre
      {-0.9 * A, 0.95 * B, true},  // inside, near a corner
      {1.7 * A, 0.4 * B, true},    // outside in x, within the y range
      {-0.2 * A, -2.6 * B, true},  // outside in y, within the x range
      {2.5 * A, -3.1 * B, false},  // outside in both: no mixed signs
      {A, 0.3 * B, true},          // on the cell's edge x = a
      {A, 2.5 * B, false},         // on the edge line x = a, beyond the cell
      {-3.0 * A, B, false},        // on the edge line y = b, beyond the cell
      {0.4 * A, -B, true},         // on the edge y = -b
      {A, B, false},               // a corner
  };
  return pts;
}

// Love's closed forms are corner sums of terms of size ~ R asinh(R/h) at distance R, whose
// result is ~ h^2/R: the cancellation costs ~ (R/h)^2 ln(R/h) units of round-off. For R <= 10 h
// that is < 2e3 eps ~ 5e-13, hence 1e-12 (relative to the integral's own size).
constexpr double kLoveTol = 1e-12;

TEST(Love, I1MatchesQuadratureOfInverseDistance) {
  for (const auto& p : test_points()) {
    const double ref = cell_quadrature(inv_r, p.x, p.y, A, B);
    const double got = love::I1(p.x, p.y, A, B);
    EXPECT_NEAR(got, ref, kLoveTol * std::fabs(ref)) << "at (" << p.x << ", " << p.y << ")";
    if (p.mixed) {
      // The abs-free form must fail here, otherwise this point tests nothing.
      EXPECT_GT(std::fabs(I1_without_abs(p.x, p.y, A, B) - ref), 1e-3 * std::fabs(ref))
          << "at (" << p.x << ", " << p.y << ")";
    }
  }
}

TEST(Love, SecondMomentsMatchQuadrature) {
  for (const auto& p : test_points()) {
    const double rxx = cell_quadrature(xx_r3, p.x, p.y, A, B);
    const double ryy = cell_quadrature(yy_r3, p.x, p.y, A, B);
    const double rxy = cell_quadrature(xy_r3, p.x, p.y, A, B);
    // Ixy vanishes on the symmetry lines; judge it against the size of the other moments.
    const double scale = std::max(std::fabs(rxx), std::fabs(ryy));
    EXPECT_NEAR(love::Ixx(p.x, p.y, A, B), rxx, kLoveTol * scale) << p.x << ", " << p.y;
    EXPECT_NEAR(love::Iyy(p.x, p.y, A, B), ryy, kLoveTol * scale) << p.x << ", " << p.y;
    EXPECT_NEAR(love::Ixy(p.x, p.y, A, B), rxy, kLoveTol * scale) << p.x << ", " << p.y;
    // Trace identity x^2/r^3 + y^2/r^3 = 1/r.
    EXPECT_NEAR(love::Ixx(p.x, p.y, A, B) + love::Iyy(p.x, p.y, A, B), love::I1(p.x, p.y, A, B),
                kLoveTol * scale);
  }
}

TEST(Love, FarFieldAgreesWithTensorQuadrature) {
  // 10 cell sizes away the integrand is smooth: plain Gauss–Legendre converges to round-off.
  for (auto [x, y] : {std::pair{10.0, 0.0}, {6.0, -8.0}, {-7.0, 7.0}}) {
    EXPECT_NEAR(love::I1(x, y, A, B), cell_tensor_quadrature(inv_r, x, y, A, B),
                kLoveTol * love::I1(x, y, A, B));
    EXPECT_NEAR(love::Ixy(x, y, A, B), cell_tensor_quadrature(xy_r3, x, y, A, B),
                kLoveTol * love::I1(x, y, A, B));
  }
}

// ---------------------------------------------------------------------------------------------
// HalfSpace operator
// ---------------------------------------------------------------------------------------------

Material steel_like(double nu) {
  Material m;
  m.body1 = Body{210e9, nu};
  return m;
}

Field random_field(int nx, int ny, unsigned seed, double lo = 0.0, double hi = 1e6) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(lo, hi);
  Field f(nx, ny);
  for (Eigen::Index k = 0; k < f.size(); ++k) f(k) = u(rng);
  return f;
}

double rel_max_diff(const Field& a, const Field& b) {
  return (a - b).abs().maxCoeff() / b.abs().maxCoeff();
}

// The own-cell response of one loaded cell is Love's coefficient at the centre, and that equals
// the quadrature of 1/r: P I1(0, 0) / (pi E*).
TEST(HalfSpace, SingleCellMatchesLoveAndQuadrature) {
  const Grid grid{32, 24, 1e-5, false};
  const Material mat = steel_like(0.3);
  HalfSpace hs(grid, mat, Coupling::analogy);
  const double P = 1e6, a = 0.5 * grid.h;
  Field p = grid.zeros(), u;
  const int si = 3, sj = 4;
  p(si, sj) = P;
  hs.normal(p, u);
  const double cz = P / (pi * mat.E_star());
  // FFT round-off: ~ eps log2(N) relative to the largest displacement; 1e-12 leaves margin.
  const double tol = 1e-12 * u.abs().maxCoeff();
  for (int j = 0; j < grid.ny; ++j)
    for (int i = 0; i < grid.nx; ++i)
      ASSERT_NEAR(u(i, j), cz * love::I1((i - si) * grid.h, (j - sj) * grid.h, a, a), tol)
          << i << ", " << j;
  EXPECT_NEAR(u(si, sj), cz * cell_quadrature(inv_r, 0, 0, a, a), tol);
  EXPECT_NEAR(hs.normal_self(), u(si, sj) / P, 1e-12 * hs.normal_self());
  // Mixed-sign corner offsets arise only at the own cell's row and column: check one by
  // quadrature, independent of love.cpp.
  EXPECT_NEAR(u(si + 5, sj), cz * cell_quadrature(inv_r, 5 * grid.h, 0, a, a), tol);

  // Far field: Boussinesq's point force P h^2 / (pi E* r) at r = 10 h. The cell's finite size
  // adds (h^2/24) Lap(1/r) / (1/r) = h^2/(24 r^2) ~ 4e-4 relative, inside the 1e-3 asked.
  for (auto [di, dj] : {std::pair{10, 0}, {6, 8}, {0, 10}}) {
    const double r = std::hypot(di, dj) * grid.h;
    const double point = P * grid.h * grid.h / (pi * mat.E_star() * r);
    EXPECT_NEAR(u(si + di, sj + dj), point, 1e-3 * point) << di << ", " << dj;
    // The discrepancy is the cell-size term, not noise: it has the predicted size; the next
    // term is O(h^4/r^4) ~ 1e-6.
    EXPECT_NEAR(u(si + di, sj + dj) / point - 1.0, grid.h * grid.h / (24 * r * r), 1e-5);
  }
}

// Cerruti point-force limit (Johnson eq. 3.86a) from E and nu directly, not via Material:
// u_x = (1+nu)/(2 pi E) Q [2(1-nu)/r + 2 nu x^2/r^3], u_y = (1+nu)/(2 pi E) Q 2 nu x y / r^3.
TEST(HalfSpace, CerrutiFarFieldMatchesPointForce) {
  const double E = 210e9, nu = 0.3;
  const Grid grid{40, 40, 1e-5, false};
  HalfSpace hs(grid, steel_like(nu), Coupling::cerruti);
  const double Q = 1e6;
  Field tx = grid.zeros(), ty = grid.zeros(), ux, uy;
  tx(2, 2) = Q;
  hs.tangential(tx, ty, ux, uy);
  const double c = (1 + nu) / (2 * pi * E) * Q * grid.h * grid.h;
  for (auto [di, dj] : {std::pair{10, 0}, {6, 8}, {8, 6}, {0, 10}}) {
    const double x = di * grid.h, y = dj * grid.h, r = std::hypot(x, y);
    const double ex = c * (2 * (1 - nu) / r + 2 * nu * x * x / (r * r * r));
    const double ey = c * 2 * nu * x * y / (r * r * r);
    // Same cell-size argument as for Boussinesq: O(h^2/r^2) ~ 1e-3 at r = 10 h.
    EXPECT_NEAR(ux(2 + di, 2 + dj), ex, 1e-3 * std::fabs(ex)) << di << ", " << dj;
    EXPECT_NEAR(uy(2 + di, 2 + dj), ey, 1e-3 * std::fabs(ex)) << di << ", " << dj;
  }
}

// Direct O(n^4) linear convolution with Love's coefficients on a small non-square grid.
struct Direct {
  Grid g;
  Material m;
  Field normal(const Field& p) const {
    const double a = 0.5 * g.h, cz = 1.0 / (pi * m.E_star());
    Field u = g.zeros();
    for (int j = 0; j < g.ny; ++j)
      for (int i = 0; i < g.nx; ++i)
        for (int l = 0; l < g.ny; ++l)
          for (int k = 0; k < g.nx; ++k)
            u(i, j) += cz * love::I1((i - k) * g.h, (j - l) * g.h, a, a) * p(k, l);
    return u;
  }
  void cerruti(const Field& tx, const Field& ty, Field& ux, Field& uy) const {
    const double a = 0.5 * g.h, ca = m.cerruti_a(), cb = m.cerruti_b();
    ux = g.zeros(), uy = g.zeros();
    for (int j = 0; j < g.ny; ++j)
      for (int i = 0; i < g.nx; ++i)
        for (int l = 0; l < g.ny; ++l)
          for (int k = 0; k < g.nx; ++k) {
            const double x = (i - k) * g.h, y = (j - l) * g.h;
            const double i1 = love::I1(x, y, a, a);
            const double kxx = ca * i1 + cb * love::Ixx(x, y, a, a);
            const double kyy = ca * i1 + cb * love::Iyy(x, y, a, a);
            const double kxy = cb * love::Ixy(x, y, a, a);
            ux(i, j) += kxx * tx(k, l) + kxy * ty(k, l);
            uy(i, j) += kxy * tx(k, l) + kyy * ty(k, l);
          }
  }
};

// FFT accuracy: round-off ~ eps log2(N) ||u||, N = 24 x 18 padded: ~1e-15; 1e-12 as asked.
constexpr double kFftTol = 1e-12;

TEST(HalfSpace, FreeConvolutionEqualsDirectSum) {
  const Grid grid{12, 9, 2e-6, false};
  const Material mat = steel_like(0.3);
  const Direct direct{grid, mat};
  const Field p = random_field(grid.nx, grid.ny, 1), q = random_field(grid.nx, grid.ny, 2, -1e6);
  Field u;

  HalfSpace hs(grid, mat, Coupling::analogy);
  hs.normal(p, u);
  const Field u_ref = direct.normal(p);
  EXPECT_LE(rel_max_diff(u, u_ref), kFftTol);
  EXPECT_EQ(hs.convolutions(), 1);

  // Analogy: (E*/G*) K_z componentwise.
  const double ratio = mat.E_star() / mat.G_star();
  hs.tangential_analogy(q, u);
  EXPECT_LE(rel_max_diff(u, ratio * direct.normal(q)), kFftTol);
  Field ux, uy;
  hs.tangential(p, q, ux, uy);
  EXPECT_LE(rel_max_diff(ux, ratio * u_ref), kFftTol);
  EXPECT_LE(rel_max_diff(uy, ratio * direct.normal(q)), kFftTol);

  // Cerruti, nu = 0.3: cross terms included.
  HalfSpace hc(grid, mat, Coupling::cerruti);
  Field rx, ry;
  direct.cerruti(p, q, rx, ry);
  hc.tangential(p, q, ux, uy);
  EXPECT_LE(rel_max_diff(ux, rx), kFftTol);
  EXPECT_LE(rel_max_diff(uy, ry), kFftTol);
  // The cross terms matter at this Poisson ratio (else the comparison above is weak).
  Field rx0, ry0;
  direct.cerruti(p, grid.zeros(), rx0, ry0);
  EXPECT_GT(ry0.abs().maxCoeff(), 1e-3 * rx0.abs().maxCoeff());
}

// Reciprocity (Betti): the response at j to a unit load at i equals the response at i to a
// unit load at j, for the normal operator and across the Cerruti x-y coupling.
TEST(HalfSpace, ReciprocalSymmetry) {
  for (bool periodic : {false, true}) {
    const Grid grid{16, 11, 1e-6, periodic};
    HalfSpace hs(grid, steel_like(0.3), Coupling::cerruti);
    std::mt19937 rng(7);
    std::uniform_int_distribution<int> ri(0, grid.nx - 1), rj(0, grid.ny - 1);
    for (int trial = 0; trial < 6; ++trial) {
      const int i1 = ri(rng), j1 = rj(rng), i2 = ri(rng), j2 = rj(rng);
      Field e1 = grid.zeros(), e2 = grid.zeros(), z = grid.zeros(), u1, u2, ux1, uy1, ux2, uy2;
      e1(i1, j1) = 1.0, e2(i2, j2) = 1.0;
      hs.normal(e1, u1);
      hs.normal(e2, u2);
      const double tol = 1e-12 * hs.normal_self();
      EXPECT_NEAR(u1(i2, j2), u2(i1, j1), tol) << periodic;
      hs.tangential(e1, z, ux1, uy1);  // x traction at 1
      hs.tangential(z, e2, ux2, uy2);  // y traction at 2
      EXPECT_NEAR(uy1(i2, j2), ux2(i1, j1), tol) << periodic;
    }
  }
}

TEST(HalfSpace, CerrutiWithZeroPoissonEqualsAnalogy) {
  for (bool periodic : {false, true}) {
    const Grid grid{14, 10, 1e-6, periodic};
    const Material mat = steel_like(0.0);
    HalfSpace ha(grid, mat, Coupling::analogy), hc(grid, mat, Coupling::cerruti);
    const Field tx = random_field(grid.nx, grid.ny, 3, -1, 1);
    const Field ty = random_field(grid.nx, grid.ny, 4, -1, 1);
    Field ax, ay, cx, cy;
    ha.tangential(tx, ty, ax, ay);
    hc.tangential(tx, ty, cx, cy);
    // Periodic spectra come from separately truncated alias sums of the same symbols; both are
    // exact functions of nu, so with nu = 0 they are identical up to round-off.
    EXPECT_LE(rel_max_diff(cx, ax), kFftTol) << periodic;
    EXPECT_LE(rel_max_diff(cy, ay), kFftTol) << periodic;
  }
}

// A study's worker builds one operator per member: with kept samples the second operator of a
// grid samples no kernel and is bit for bit the one a fresh process builds; another material,
// coupling or grid samples afresh.
TEST(HalfSpace, KeptKernelSamplesGiveTheFreshOperatorBitForBit) {
  const Grid grid{14, 10, 1e-6, false};
  const Field p = random_field(grid.nx, grid.ny, 5, 0, 1);
  const Field tx = random_field(grid.nx, grid.ny, 6, -1, 1);
  const Field ty = random_field(grid.nx, grid.ny, 7, -1, 1);
  struct Out {
    Field uz, ux, uy;
  };
  auto apply = [&](const Material& mat, Coupling coupling, const Grid& g) {
    HalfSpace hs(g, mat, coupling);
    Out o;
    hs.normal(p, o.uz);
    hs.tangential(tx, ty, o.ux, o.uy);
    return o;
  };
  const Out fresh = apply(steel_like(0.3), Coupling::cerruti, grid);
  keep_kernel_samples(true);
  const std::int64_t n0 = kernel_samples_computed();
  apply(steel_like(0.3), Coupling::cerruti, grid);
  EXPECT_EQ(kernel_samples_computed(), n0 + 1);
  const Out kept = apply(steel_like(0.3), Coupling::cerruti, grid);
  EXPECT_EQ(kernel_samples_computed(), n0 + 1) << "the same grid and material sampled again";
  EXPECT_TRUE((kept.uz == fresh.uz).all() && (kept.ux == fresh.ux).all() &&
              (kept.uy == fresh.uy).all());
  apply(steel_like(0.2), Coupling::cerruti, grid);
  apply(steel_like(0.2), Coupling::analogy, grid);
  apply(steel_like(0.2), Coupling::analogy, Grid{14, 12, 1e-6, false});
  EXPECT_EQ(kernel_samples_computed(), n0 + 4);
  const Out again = apply(steel_like(0.3), Coupling::cerruti, grid);
  EXPECT_TRUE((again.uz == fresh.uz).all() && (again.ux == fresh.ux).all());
  keep_kernel_samples(false);
  apply(steel_like(0.3), Coupling::cerruti, grid);
  apply(steel_like(0.3), Coupling::cerruti, grid);
  EXPECT_EQ(kernel_samples_computed(), n0 + 7) << "kept with keep_kernel_samples(false)";
}

TEST(HalfSpace, SparseAddEqualsConvolution) {
  for (bool periodic : {false, true}) {
    const Grid grid{20, 13, 1e-6, periodic};
    HalfSpace hs(grid, steel_like(0.3), Coupling::analogy);
    const Field p = random_field(grid.nx, grid.ny, 5);
    Field u, full;
    hs.normal(p, u);
    // Corners, edges and interior nodes: the wrap-around of negative offsets is exercised.
    const std::vector<std::int64_t> idx = {
        0,   grid.nx - 1, std::int64_t(grid.size()) - 1, std::int64_t(grid.size()) - grid.nx, 47,
        133, 200};
    const std::vector<double> val = {1e5, -2e5, 3e5, 4e4, -5e5, 6e5, 7e5};
    Field pe = p;
    for (std::size_t k = 0; k < idx.size(); ++k) pe(idx[k]) += val[k];
    hs.normal_add_sparse(idx, val, u);
    hs.normal(pe, full);
    EXPECT_LE(rel_max_diff(u, full), kFftTol) << periodic;

    // Tangential analogy variant: scaled by E*/G*.
    Field ut = grid.zeros();
    hs.tangential_add_sparse(idx, val, ut);
    Field sparse_only = grid.zeros();
    for (std::size_t k = 0; k < idx.size(); ++k) sparse_only(idx[k]) = val[k];
    Field ref;
    hs.tangential_analogy(sparse_only, ref);
    EXPECT_LE(rel_max_diff(ut, ref), kFftTol) << periodic;
  }
}

// The update restricted to target nodes gives add_sparse's bits on the targets (the same terms
// in the same order) and leaves every other node as it was; free and periodic grids, targets
// in the first, last and interior rows, left and right of the nodes (both wrap-arounds).
TEST(HalfSpace, SparseAddAtTargetsIsBitwiseTheFullOne) {
  for (bool periodic : {false, true}) {
    const Grid grid{20, 13, 1e-6, periodic};
    HalfSpace hs(grid, steel_like(0.3), Coupling::analogy);
    const std::vector<std::int64_t> idx = {0, grid.nx - 1, 47, 133, std::int64_t(grid.size()) - 1};
    const std::vector<double> val = {1e5, -2e5, 3e5, 4e4, -5e5};
    std::vector<std::int64_t> targets;
    for (std::int64_t k = 0; k < std::int64_t(grid.size()); k += 3) targets.push_back(k);
    const Field start = random_field(grid.nx, grid.ny, 7);
    Field full = start, at = start;
    hs.tangential_add_sparse(idx, val, full);
    hs.tangential_add_sparse_at(idx, val, targets, at);
    std::size_t t = 0;
    for (std::int64_t k = 0; k < std::int64_t(grid.size()); ++k) {
      const bool target = t < targets.size() && targets[t] == k;
      EXPECT_EQ(at(k), target ? full(k) : start(k)) << periodic << " node " << k;
      t += target;
    }
  }
}

// Lattice sum S3 = sum over m in Z^2 \ {0} of |m|^-3, summed to |m_i| <= M plus the integral of
// the tail, 2 pi / M (error O(M^-2)).
double lattice_sum3() {
  constexpr int M = 400;
  double s = 0.0;
  for (int i = -M; i <= M; ++i)
    for (int j = -M; j <= M; ++j)
      if (i || j) s += std::pow(double(i) * i + double(j) * j, -1.5);
  // Tail outside the square: integral of r^-3 over the plane outside a square of half-side
  // M + 1/2 is ~ 2 pi / (M + 1/2) (round-annulus approximation, error ~1e-6 here).
  return s + 2 * pi / (M + 0.5);
}

// Periodic vs free boundary for a compact load in the middle of the cell. The periodic field is
// the free one plus the images' field (minus the mean load). Near the load the images add a
// constant plus a quadratic: the Hessian of sum_m 1/|x - m L| at x = 0 is (S3 / (2 L^3)) I by
// the square lattice's symmetry (trace of the in-plane Hessian of 1/r is 1/r^3), and a uniform
// background load has no in-plane curvature. So
//   u_per - u_free = c + F S3 / (4 pi E* L^3) |x - x_c|^2 + O(F rho^4 / (E* L^5)),
// x_c the load's centroid. The test checks (1) the two agree up to a constant within the
// quadratic's size at radius rho, (2) that the quadratic is the whole difference, up to the
// next term of the expansion.
TEST(HalfSpace, PeriodicMatchesFreeNearCompactLoad) {
  const int n = 64;
  const double L = 1e-3;
  const Material mat = steel_like(0.3);
  const Grid gf = Grid::square(n, L, false), gp = Grid::square(n, L, true);
  HalfSpace hf(gf, mat, Coupling::analogy), hp(gp, mat, Coupling::analogy);
  const double h = gf.h, R = 4 * h;  // load: Hertz-like bump of radius 4 h at the centre
  Field p = gf.zeros();
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const double r2 = gf.x(i) * gf.x(i) + gf.y(j) * gf.y(j);
      if (r2 < R * R) p(i, j) = 1e8 * std::sqrt(1 - r2 / (R * R));
    }
  const double F = p.sum() * h * h;
  Field uf, up;
  hf.normal(p, uf);
  hp.normal(p, up);
  const double rho = 8 * h;
  const double c2 = F * lattice_sum3() / (4 * pi * mat.E_star() * L * L * L);
  std::vector<double> d, r2s;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const double r2 = gf.x(i) * gf.x(i) + gf.y(j) * gf.y(j);
      if (r2 <= rho * rho) d.push_back(up(i, j) - uf(i, j)), r2s.push_back(r2);
    }
  double mean = 0.0, mean_q = 0.0;
  for (std::size_t k = 0; k < d.size(); ++k) mean += d[k], mean_q += d[k] - c2 * r2s[k];
  mean /= d.size(), mean_q /= d.size();
  double dev = 0.0, dev_q = 0.0;
  for (std::size_t k = 0; k < d.size(); ++k) {
    dev = std::max(dev, std::fabs(d[k] - mean));
    dev_q = std::max(dev_q, std::fabs(d[k] - c2 * r2s[k] - mean_q));
  }
  const double u_scale = uf.maxCoeff();
  // (1) Up to a constant shift the fields differ by less than the quadratic's full swing
  // c2 rho^2 (~1e-3 of the peak displacement here).
  EXPECT_LE(dev, c2 * rho * rho);
  EXPECT_LE(dev, 2e-3 * u_scale);
  // (2) The next term is ~ F/(pi E*) * (rho^4 / L^5) * sum |m|^-5 (~5.0): with rho/L = 1/8,
  // that is (rho/L)^2 * 5/9 ~ 1e-2 of the quadratic's swing. The periodic spectrum's alias-sum
  // truncation adds ~1e-5 of the displacement. Allow 5e-2 of the swing.
  EXPECT_LE(dev_q, 5e-2 * c2 * rho * rho);
  RecordProperty("periodic_free_dev_rel", std::to_string(dev / u_scale));
  RecordProperty("dev_over_swing", std::to_string(dev / (c2 * rho * rho)));
  RecordProperty("devq_over_swing", std::to_string(dev_q / (c2 * rho * rho)));
  RecordProperty("periodic_free_dev_after_quadratic_rel", std::to_string(dev_q / u_scale));
}

}  // namespace
}  // namespace fretbem
