// The conjugate-gradient loop that the normal, tangential and stiffness solves share: the
// residual watch (best and last residual), the confirmation of a converged residual on an
// exact product, and the conjugacy recurrence beta = G / G_old with its restarts. What the
// solves do differently is the Problem's, a strategy object with these members:
//
//   double residual();                        relative residual of the current iterate
//   cg::Next on_residual(int it, const cg::Watch&);   e.g. a cold start when the residual stalls
//   void refresh();                           exact product, dropping incremental round-off
//   bool exhausted(int it, const cg::Watch&); stop without convergence (iterations, stagnation)
//   double gradient_product();                G = r . z, z the (preconditioned) gradient
//   cg::Step step(double beta);               direction z + beta d, its image, step length,
//                                             step, projection onto the constraints
//
// The loop does no arithmetic on the iterate itself, so each solve keeps its own operation
// order (and its results bit for bit).
#pragma once

#include <limits>

namespace fretbem::cg {

/// Smallest tolerance at which a solve may end on its incrementally updated image without the
/// verifying product (double-precision FFTs only): each update of the image carries the
/// product's round-off, ~1e-15 of its size (log2 of the padded size times the unit
/// round-off), and the updates sum to about the start's distance from the solution, so the
/// drift of the residual stays three decades below this.
inline constexpr double kUnverifiedTolerance = 1e-11;

/// What the loop does after a problem's hook.
enum class Next {
  proceed,  ///< go on with this iteration
  restart,  ///< the problem started afresh (a cold start): new residual watch, new Krylov space
  stop      ///< leave the loop; the last residual decides convergence
};

/// Outcome of Problem::step: what comes next, and whether conjugacy restarts (beta = 0) in the
/// next iteration because the step changed the constrained set.
struct Step {
  Next next = Next::proceed;
  bool restart = false;
};

/// The residuals seen so far: the best one and the iteration that reached it, and the last.
struct Watch {
  double best = std::numeric_limits<double>::infinity();
  int best_it = 0;
  double last = std::numeric_limits<double>::infinity();
};

/// The loop's rules, a few flags each solve sets.
struct Rules {
  double tolerance = 0.0;  ///< relative residual at which the iterate is converged
  /// Last iteration index whose residual is evaluated (normal solve: max_iterations; the
  /// others stop through Problem::exhausted).
  int last_pass = std::numeric_limits<int>::max() - 1;
  /// A residual at the tolerance is confirmed once after Problem::refresh before the loop
  /// ends: incremental updates of the image drift by round-off.
  bool verify = true;
  bool verified_at_start = false;     ///< the start was imaged exactly: nothing to confirm
  bool restart_after_verify = false;  ///< the refreshed image starts a new Krylov space
  /// Residual growth by this factor in one iteration restarts conjugacy (a change from
  /// outside the recurrence); infinite: never.
  double jump = std::numeric_limits<double>::infinity();
};

struct Outcome {
  int iterations = 0;
  double residual = 0.0;
  bool converged = false;
};

template <class Problem>
Outcome run(Problem& p, const Rules& rules) {
  Outcome out;
  Watch watch;
  bool restart = true, verified = rules.verified_at_start;
  double g_old = 1.0;
  auto start_afresh = [&] {
    restart = true;
    watch.best = std::numeric_limits<double>::infinity();
  };
  for (int it = 0; it <= rules.last_pass; ++it) {
    out.iterations = it;
    out.residual = p.residual();
    if (out.residual > rules.jump * watch.last) restart = true;
    watch.last = out.residual;
    if (out.residual < watch.best) watch.best = out.residual, watch.best_it = it;
    if (p.on_residual(it, watch) == Next::restart) {
      start_afresh();
      continue;
    }
    if (out.residual <= rules.tolerance) {
      if (verified || !rules.verify) {
        out.converged = true;
        break;
      }
      p.refresh();
      verified = true;
      if (rules.restart_after_verify) restart = true;
      continue;
    }
    verified = false;
    if (p.exhausted(it, watch)) break;
    const double G = p.gradient_product();
    const double beta = restart ? 0.0 : G / g_old;
    g_old = G;
    const Step s = p.step(beta);
    if (s.next == Next::stop) break;
    if (s.next == Next::restart) {
      start_afresh();
      continue;
    }
    restart = s.restart;
  }
  return out;
}

}  // namespace fretbem::cg
