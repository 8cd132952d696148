// What the ODE wear integrators hand to SUNDIALS: the run's state behind ARKODE's user data,
// and the callbacks that evaluate the wear map and solve with the frozen-slip Newton matrix.
// Internal to src/wear.
#pragma once

#include <arkode/arkode.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sundials/sundials_linearsolver.h>

#include <exception>
#include <memory>

#include "fretbem/wear/integrator.hpp"
#include "fretbem/wear/preconditioner.hpp"

namespace fretbem::wear_detail {

/// A SUNDIALS context owned for the run.
struct SunContext {
  SUNContext ctx = nullptr;
  SunContext();
  ~SunContext();
  SunContext(const SunContext&) = delete;
  SunContext& operator=(const SunContext&) = delete;
};

/// ARKODE's user data: the model and cycles the wear map runs on, the report its rows go to.
struct OdeData {
  OdeData(Model& m, WearCycles& c, WearReport& r) : model(m), cyc(c), rep(r) {}
  Model& model;
  WearCycles& cyc;
  WearReport& rep;
  double atol = 0.0;           // absolute tolerance on W (m): wear.atol, or rtol x indentation
  double step_max_slip = 0.0;  // largest slip per cycle seen in the current integrator step
  std::exception_ptr error;
  // Implicit mode: the last evaluation at an iterate (not a Jacobian probe) linearises the
  // Newton matrix (WearPreconditioner), and a repeated iterate on its worn depth base_worn is
  // answered with its rate (same_worn_depth).
  std::unique_ptr<WearPreconditioner> pre;
  bool probing = false;
  Field base_worn, base_pressure, base_rate;
  long base_generation = 0, linearised_generation = -1;
};

/// This rank's slab of a grid vector (nx, local rows), in place.
Eigen::Map<Field> slab(const OdeData& d, N_Vector v);
/// A vector owned with the function that frees it.
using GridVector = std::unique_ptr<_generic_N_Vector, void (*)(N_Vector)>;
/// A grid vector of hs's grid (grid_vector.cpp): serial, or on a distributed grid SUNDIALS'
/// MPI+X vector over a serial one holding this rank's slab, whose reductions are over all
/// ranks.
GridVector new_grid_vector(const HalfSpace& hs, SUNContext ctx);
/// dW/dN = w(z0 - W) (m per cycle) at N: one steady cycle on the surface worn by y.
int wear_rhs(realtype N, N_Vector y, N_Vector ydot, void* user);
/// ARKODE's error handler: silent (failures are reported by `check`).
void silent(int, const char*, const char*, char*, void*);
/// x = P^-1 b with the frozen-slip Newton matrix P = I - gamma J~, the inner CG residual at
/// most `residual` (m, 2-norm; 0: WearPreconditioner's relative tolerance).
int newton_matrix_solve(OdeData& d, N_Vector b, N_Vector x, double gamma, double residual = 0.0);
/// Krylov Newton (wear.newton = krylov): preconditioner setup and solve, J v products.
int wear_psetup(realtype, N_Vector, N_Vector, booleantype, booleantype* jcur, realtype, void*);
int wear_psolve(realtype, N_Vector, N_Vector, N_Vector r, N_Vector z, realtype gamma, realtype, int,
                void* user);
int wear_jtimes(N_Vector v, N_Vector Jv, realtype N, N_Vector y, N_Vector fy, void* user,
                N_Vector tmp);
/// The matrix-embedded linear solver of the frozen Newton (wear.newton = frozen) for the
/// ARKStep memory `arkode`.
SUNLinearSolver frozen_slip_solver(OdeData& d, void* arkode, SUNContext ctx);

}  // namespace fretbem::wear_detail
