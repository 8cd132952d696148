// The conjugate-gradient loop shared by the normal, tangential and stiffness solves (cg::run)
// against linear algebra it does not compute: on a symmetric positive definite system it is
// plain CG, which reaches the solution within the system's dimension; a residual met by
// incremental updates is confirmed on an exact product; a problem's cold start begins a new
// Krylov space.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <cstdlib>
#include <vector>

#include "fretbem/contact/cg_core.hpp"

using namespace fretbem;

namespace {

// Plain CG for A x = b as a cg::run problem; r = b - A x is updated incrementally, as the
// solvers update their images. `drift` is added to r after every step to imitate round-off
// that only an exact product removes.
struct LinearProblem {
  Eigen::MatrixXd A;
  Eigen::VectorXd b, x, r, d;
  double drift = 0.0;
  int refreshes = 0, max_iterations = 1000;

  LinearProblem(const Eigen::MatrixXd& A_, const Eigen::VectorXd& b_)
      : A(A_), b(b_), x(Eigen::VectorXd::Zero(b_.size())), r(b_), d(b_.size()) {}

  double residual() { return r.norm() / b.norm(); }
  cg::Next on_residual(int, const cg::Watch&) { return cg::Next::proceed; }
  void refresh() { r = b - A * x, ++refreshes; }
  bool exhausted(int it, const cg::Watch&) const { return it >= max_iterations; }
  double gradient_product() { return r.squaredNorm(); }
  cg::Step step(double beta) {
    const double G = r.squaredNorm();
    d = r + beta * d;
    const Eigen::VectorXd q = A * d;
    const double alpha = G / d.dot(q);
    x += alpha * d;
    r -= alpha * q;
    r.array() += drift;
    return {cg::Next::proceed, false};
  }
};

Eigen::MatrixXd spd(int n) {
  std::srand(7);
  const Eigen::MatrixXd B = Eigen::MatrixXd::Random(n, n);
  return B.transpose() * B + Eigen::MatrixXd::Identity(n, n);
}

}  // namespace

TEST(CgCore, PlainCgReachesTheSolutionWithinTheDimension) {
  const int n = 24;
  const Eigen::MatrixXd A = spd(n);
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(n, -1.0, 2.0);
  const Eigen::VectorXd exact = A.ldlt().solve(b);
  LinearProblem p(A, b);
  cg::Rules rules;
  rules.tolerance = 1e-12;
  const cg::Outcome out = cg::run(p, rules);
  ASSERT_TRUE(out.converged);
  // n conjugate steps in exact arithmetic; a few more for round-off on this conditioning,
  // plus the confirming pass.
  EXPECT_LE(out.iterations, 2 * n);
  EXPECT_LT((p.x - exact).norm() / exact.norm(), 1e-10);
  EXPECT_EQ(p.refreshes, 1);  // one exact product confirms the incremental residual
}

TEST(CgCore, DriftedResidualIsConfirmedOnAnExactProduct) {
  const int n = 12;
  const Eigen::MatrixXd A = spd(n);
  const Eigen::VectorXd b = Eigen::VectorXd::Ones(n);
  const Eigen::VectorXd exact = A.ldlt().solve(b);
  // The incremental residual drifts by 1e-9 per component and step: at its apparent
  // convergence the exact product shows the true residual, and the loop ends only on a
  // residual at the tolerance right after an exact product.
  LinearProblem p(A, b);
  p.drift = 1e-9;
  cg::Rules rules;
  rules.tolerance = 1e-8;
  const cg::Outcome out = cg::run(p, rules);
  ASSERT_TRUE(out.converged);
  EXPECT_GE(p.refreshes, 1);
  EXPECT_LT((b - A * p.x).norm() / b.norm(), 1e-7);
  EXPECT_LT((p.x - exact).norm() / exact.norm(), 1e-6);

  // Without confirmation the loop takes the incremental residual's word.
  LinearProblem q(A, b);
  rules.verify = false;
  ASSERT_TRUE(cg::run(q, rules).converged);
  EXPECT_EQ(q.refreshes, 0);
}

TEST(CgCore, ColdStartRestartsConjugacyAndTheWatch) {
  // A problem that asks for a cold start once, at iteration 3: the next direction must be the
  // plain gradient (beta = 0) and the best residual forgotten.
  struct Restarting : LinearProblem {
    using LinearProblem::LinearProblem;
    std::vector<double> betas;
    int best_after_restart = -1;
    bool restarted = false;
    cg::Next on_residual(int it, const cg::Watch& w) {
      if (restarted && best_after_restart < 0) best_after_restart = w.best_it;
      if (it == 3 && !restarted) {
        restarted = true;
        x.setZero(), r = b;  // back to the start
        return cg::Next::restart;
      }
      return cg::Next::proceed;
    }
    cg::Step step(double beta) {
      betas.push_back(beta);
      return LinearProblem::step(beta);
    }
  };
  const Eigen::MatrixXd A = spd(10);
  Restarting p(A, Eigen::VectorXd::Ones(10));
  cg::Rules rules;
  rules.tolerance = 1e-12;
  ASSERT_TRUE(cg::run(p, rules).converged);
  ASSERT_GE(p.betas.size(), 5u);
  EXPECT_EQ(p.betas[0], 0.0);
  EXPECT_GT(p.betas[1], 0.0);
  EXPECT_EQ(p.betas[3], 0.0);          // the first step after the cold start
  EXPECT_EQ(p.best_after_restart, 4);  // the watch starts again at the restart's residual
}
