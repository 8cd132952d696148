// FailedSolve: the inputs of a normal or tangential solve that did not converge, carried by
// IncrementFailure from the stepper to the command line, which writes them to
// DIR/failed_solve.h5 (io/failed_solve.hpp) so that the failure can be reproduced alone.
#pragma once

#include <Eigen/Core>
#include <filesystem>
#include <string>

#include "fretbem/contact/tangential_operator.hpp"
#include "fretbem/core/errors.hpp"

namespace fretbem {

struct FailedSolve {
  std::string solve;       ///< "normal" or "tangential"
  std::string control;     ///< force, indentation (normal); force, displacement (tangential)
  Eigen::VectorXd target;  ///< normal: F_z (N) or delta (m); tangential: F (N) or dU (m), local
  Field surface;           ///< normal: indenter height z (m)
  Field pressure_start;    ///< normal: warm-start pressure (Pa)
  Field bound;             ///< tangential: g = mu p (Pa)
  VecField tau0, u0;       ///< tangential: previous step's traction (Pa) and C tau0 (m)
  Eigen::Vector2d direction{1.0, 0.0};  ///< tangential, one component: its unit direction
  std::string scenario;                 ///< the resolved scenario text, when known
};

/// A solve that failed after every fallback: the message names the step and cycle, `inputs`
/// hold what reproduces it, `dir` is the run's output directory.
struct IncrementFailure : SolverError {
  IncrementFailure(const std::string& what, FailedSolve in, std::filesystem::path out)
      : SolverError(what), inputs(std::move(in)), dir(std::move(out)) {}
  FailedSolve inputs;
  std::filesystem::path dir;
};

}  // namespace fretbem
