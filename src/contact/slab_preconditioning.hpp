// The automatic preconditioning decision (PreconditionDecision::for_set) on a grid distributed
// over MPI ranks. Internal to src/contact.
#pragma once

#include "fretbem/contact/preconditioning.hpp"
#include "fretbem/parallel/communicator.hpp"

namespace fretbem {

/// decision.for_set of the whole set on a grid of `grid`'s size distributed over the ranks of
/// `comm`, `slab` this rank's rows of the set: rank 0 decides on the gathered set and every
/// rank takes its answer.
bool for_distributed_set(const PreconditionDecision& decision, const Field& slab, const Grid& grid,
                         const Communicator& comm);

}  // namespace fretbem
