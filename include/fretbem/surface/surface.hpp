// Surface: height fields z(x, y) (m, peaks positive) of the rigid indenter — generation,
// import from files, and statistics, one header each.
#pragma once

#include "fretbem/surface/formats.hpp"
#include "fretbem/surface/generate.hpp"
#include "fretbem/surface/statistics.hpp"
