// `fretbem check`'s share of the edge-contact refusal (resolution.hpp, check_edge_contact):
// `run` refuses a sphere whose solved normal pressure puts more than kEdgeLoadShareLimit of the
// load on the outermost cells, at the first step that does so. The Hertz prediction cannot
// decide it (measured at n = 64, R = 10 mm, Fz = 10 N: Hertz 2.9, 6.5, 15.2, 35.7 % against
// solved 0.64, 1.6, 4.3, 11.3 % for grid.length = 135, 130, 120, 100 um), so check solves the
// normal problems that can decide it and refuses with run's line.
#pragma once

#include "fretbem/history/model.hpp"

namespace fretbem {

/// Throws run's InputError ("step K: ...") when a step of the path would be refused for edge
/// contact. Solves only when the Hertz prediction at the path's peak load exceeds the limit
/// (the solved share stayed below it in every measurement above), and then only the steps at
/// which the normal load reaches a new maximum, by bisection (the share grows with the load),
/// on a model it builds then (build_model).
void check_edge_contact_of_path(const Scenario& sc, const LoadPath& path);

}  // namespace fretbem
