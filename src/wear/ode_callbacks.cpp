// The SUNDIALS callbacks of the ODE wear integrators: the wear map as ARKODE's right-hand
// side, the frozen-slip Newton matrix solve, the Krylov preconditioner and J v products.
#include <arkode/arkode_arkstep.h>

#include <cmath>
#include <utility>

#include "fretbem/core/errors.hpp"
#include "ode_data.hpp"
#include "wear_rows.hpp"

namespace fretbem::wear_detail {

SunContext::SunContext() {
  if (SUNContext_Create(nullptr, &ctx) != 0) throw SolverError("SUNDIALS: no context");
}

SunContext::~SunContext() {
  SUNContext_Free(&ctx);
}

namespace {

// Whether `base` is the worn depth W on every rank: a slab that differs on one rank is a
// different state.
bool same_worn_depth(const Field& base, const Field& W, const Communicator& comm) {
  const bool same =
      base.size() > 0 && base.rows() == W.rows() && base.cols() == W.cols() && (base == W).all();
  return !comm.any(!same);
}

}  // namespace

// dW/dN = w(z0 - W): one steady cycle on the current surface per evaluation. The map is
// autonomous (a function of W alone; N only labels the row), and TR-BDF2 with the trivial
// Newton predictor starts an implicit stage from the step's start y_n bit for bit, which the
// step's first stage (or the stage before, converged at its first iterate) has just evaluated:
// in implicit mode that repeat is answered with the rate of the Newton matrix's base
// evaluation, the latest one, without a cycle. Exceptions cannot cross the C library: kept and
// rethrown after ARKODE returns.
int wear_rhs(realtype N, N_Vector y, N_Vector ydot, void* user) {
  auto& d = *static_cast<OdeData*>(user);
  try {
    // Worn depth is never negative; an implicit method's Newton iterates may overshoot below
    // zero (material added), which would raise a node above the unworn surface.
    const Field W = slab(d, y).max(0.0);
    const Communicator& comm = d.model.half_space->communicator();
    if (d.pre && !d.probing && same_worn_depth(d.base_worn, W, comm)) {
      slab(d, ydot) = d.base_rate;
      return 0;
    }
    WearCycle c = d.cyc.steady(N, W);
    slab(d, ydot) = c.rate;
    if (d.pre && !d.probing) {
      d.base_worn = W;
      d.base_pressure = d.cyc.pressure();
      d.base_rate = c.rate;
      ++d.base_generation;
    }
    d.step_max_slip = std::max(d.step_max_slip, c.max_slip);
    c.worn_hash = fingerprint(W, comm);
    // Logged once the step is done and its accepted state known (flush_step).
    keep(d.rep, std::move(c));
    return 0;
  } catch (...) {
    d.error = std::current_exception();
    return -1;
  }
}

void silent(int, const char*, const char*, char*, void*) {}

// x = P^-1 b, P = I - gamma J~ the frozen-slip Newton matrix, linearised at the latest
// evaluated iterate (relinearised only when a new iterate has been evaluated since). Shared by
// the Krylov preconditioner and the matrix-embedded linear solver. Exceptions are kept for
// rethrow after ARKODE returns.
int newton_matrix_solve(OdeData& d, N_Vector b, N_Vector x, double gamma, double residual) {
  try {
    if (d.linearised_generation != d.base_generation) {
      d.pre->setup(d.base_pressure, d.base_rate);
      d.linearised_generation = d.base_generation;
    }
    Field out;
    d.pre->solve(slab(d, b), gamma, out, residual);
    slab(d, x) = out;
    return 0;
  } catch (...) {
    d.error = std::current_exception();
    return -1;
  }
}

int wear_psetup(realtype, N_Vector, N_Vector, booleantype, booleantype* jcur, realtype, void*) {
  *jcur = SUNTRUE;  // the matrix is relinearised in the solve, at the latest iterate
  return 0;
}

int wear_psolve(realtype, N_Vector, N_Vector, N_Vector r, N_Vector z, realtype gamma, realtype, int,
                void* user) {
  return newton_matrix_solve(*static_cast<OdeData*>(user), r, z, gamma);
}

// J v by a forward difference of the wear map, [w(W + sigma v) - w(W)] / sigma, with sigma
// scaling v to unit weighted-RMS norm (ARKODE's own choice), marked as a probe so that it does
// not become the linearisation point of the preconditioner.
int wear_jtimes(N_Vector v, N_Vector Jv, realtype N, N_Vector y, N_Vector fy, void* user,
                N_Vector tmp) {
  auto& d = *static_cast<OdeData*>(user);
  const double vnorm = std::sqrt(N_VDotProd(v, v) / double(N_VGetLength(v)));
  if (vnorm == 0.0) {
    N_VConst(0.0, Jv);
    return 0;
  }
  const double W_rms = std::sqrt(N_VDotProd(y, y) / double(N_VGetLength(y)));
  const double sigma = (d.model.scenario.wear.rtol * W_rms + d.atol) / vnorm;
  N_VLinearSum(1.0, y, sigma, v, tmp);
  d.probing = true;
  const int flag = wear_rhs(N, tmp, Jv, user);
  d.probing = false;
  if (flag != 0) return flag;
  N_VLinearSum(1.0 / sigma, Jv, -1.0 / sigma, fy, Jv);
  return 0;
}

}  // namespace fretbem::wear_detail
