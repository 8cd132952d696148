// Option types of the iterative solvers that scenarios set and solvers read. They live here,
// below both, so that a scenario names a solver option without depending on the solver.
#pragma once

namespace fretbem {

/// Fourier preconditioning of the conjugate-gradient solves (solver.precondition): off, on, or
/// automatic, where each solve applies its measured break-even (contact/preconditioning.hpp).
enum class Precondition { off, on, automatic };

}  // namespace fretbem
