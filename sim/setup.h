// Initial particle placement from the scene's shapes.
#pragma once

#include "sim/params.h"

#include <vector>

namespace kurage::sim {

// Lattice points of a block: a cubic lattice of the given spacing, the first point half a
// spacing inside `min`, every point at least half a spacing inside `max`.
std::vector<Eigen::Vector3f> latticePoints(const FluidBlock& block, float spacing);

}  // namespace kurage::sim
