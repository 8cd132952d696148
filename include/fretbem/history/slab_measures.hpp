// The measures of a step (observables.hpp, resolution.hpp) of a state held in slabs of a grid
// distributed over MPI ranks (elastic/half_space.hpp): the same numbers as the serial
// functions of the whole grid, every count and sum through the grid's communicator.
#pragma once

#include "fretbem/contact/interface_state.hpp"
#include "fretbem/elastic/half_space.hpp"

namespace fretbem {

/// slip_ring_cells of the whole grid's states (resolution.hpp).
double slip_ring_cells(const StateField& slab, const HalfSpace& hs);
/// Cell edges of the whole grid between a contact node and a non-contact one or the domain's
/// edge (the perimeter of slip_ring_cells, in cells).
long contact_edges(const StateField& slab, const HalfSpace& hs);
/// contact_nodes of the whole grid's states.
long contact_nodes(const StateField& slab, const HalfSpace& hs);
/// edge_load_share of the whole grid's pressure.
double edge_load_share(const Field& slab, const HalfSpace& hs);

}  // namespace fretbem
