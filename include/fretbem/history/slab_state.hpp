// A run's per-node state on a grid distributed over MPI ranks: each rank holds the slab of
// rows j in [first_row, first_row + local_rows) of every field (elastic/half_space.hpp). The
// files of a run hold the whole grid (docs/mpi-grid.md, "A run on K ranks"): what rank 0
// writes is gathered to it, and what a resume reads is cut into slabs.
#pragma once

#include "fretbem/history/stepper.hpp"

namespace fretbem {

/// The whole grid's field on rank 0 (empty on the other ranks) from every rank's slab.
Field gathered(const HalfSpace& hs, const Field& slab);
/// This rank's slab of a whole grid's field.
Field slab_of(const HalfSpace& hs, const Field& whole);
/// The whole grid's field on every rank from every rank's slab (what a whole surface needs of
/// a worn depth). Serial: the field.
Field on_every_rank(const HalfSpace& hs, const Field& slab);

/// The stepper's state and memory with every field gathered (whole grid on rank 0, fields
/// empty elsewhere; scalars everywhere); the cycle predictor's and Masing image's memory in
/// their whole-grid flat forms.
InterfaceState gathered(const HalfSpace& hs, const InterfaceState& slab);
StepperMemory gathered(const HalfSpace& hs, const StepperMemory& slab);
/// The same cut into this rank's slabs (a resume on K ranks of a checkpoint of any K).
InterfaceState slab_of(const HalfSpace& hs, const InterfaceState& whole);
StepperMemory slab_of(const HalfSpace& hs, const StepperMemory& whole);

}  // namespace fretbem
