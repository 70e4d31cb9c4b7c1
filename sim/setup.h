// Initial particle placement from the scene's shapes.
#pragma once

#include "sim/params.h"
#include "sim/particles.h"

#include <cstdint>
#include <vector>

namespace kurage::sim {

// Lattice points of a block: a cubic lattice of the given spacing, the first point half a
// spacing inside `min`, every point at least half a spacing inside `max`.
std::vector<Eigen::Vector3f> latticePoints(const FluidBlock& block, float spacing);

// Appends the block's lattice as fluid particles (kind 0) at rest; ids continue from nextId.
void addFluidBlock(ParticleSet& particles, const FluidBlock& block, float spacing, float restDensity, float mass,
                   int64_t& nextId);

}  // namespace kurage::sim
