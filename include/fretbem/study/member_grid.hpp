// Per-member grid choice of a study: a Hertz sphere under a cyclic tangential load
// dissipates in a slip ring a (1 - (1 - q)^(1/3)) wide, and the energy per cycle is within
// 0.5 % of Mindlin–Deresiewicz only where that ring spans kMinRingCells cells or more
// (measured, resolution.hpp). Small amplitudes need finer grids than large ones: the study
// refines each member's grid to what its own amplitude needs, up to a ceiling, and says which
// members stay under-resolved.
#pragma once

#include "fretbem/scenario/scenario.hpp"
#include "fretbem/study/sweep_spec.hpp"

namespace fretbem {

/// The grid member scenario `sc` should run with: its own grid.n when its predicted slip ring
/// spans kMinRingCells cells or more (or no prediction exists), otherwise the smallest multiple
/// of 8 that resolves it, capped by max_grid_n (0: never refine, only report). The domain
/// (grid.length) is kept: refining changes the cell, not the problem.
MemberGrid choose_member_grid(const Scenario& sc, int max_grid_n);

}  // namespace fretbem
