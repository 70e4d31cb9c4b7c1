// Initial particles of a telescopic body from its shape (SPEC §3, §5): positions on a lattice of
// the body spacing and the particles of its named selection `rim`.
#pragma once

#include "sim/params.h"

#include <Eigen/Core>

#include <cstdint>
#include <vector>

namespace kurage::sim {

struct BodyPoints {
  std::vector<Eigen::Vector3f> positions;
  std::vector<uint8_t> rim;  // 1 for the particles of the selection "rim"
};

// The body's particles at t = 0; `fluidSpacing` is l_avr (the body spacing is a fraction of it).
BodyPoints bodyPoints(const BodyParams& body, float fluidSpacing);

// Whether particle k of `points` belongs to a selection (for pins; springs use both ends).
bool selected(const Selection& selection, const BodyPoints& points, size_t k);

}  // namespace kurage::sim
