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
  // Distance of each particle from the body's edge, in body spacings: the selection "rim" of width
  // w is the particles with edge < max(w, 1). A membrane counts rows from its border, a shell arc
  // length from its opening (rings are one spacing apart), a chain has only its first particle at
  // 0; a box has no edge (infinity).
  std::vector<float> edge;
  float rimWidth = 1.0f;  // the body's rim_width, the width of a "rim" selection that names none
};

// The body's particles at t = 0; `fluidSpacing` is l_avr (the body spacing is a fraction of it).
BodyPoints bodyPoints(const BodyParams& body, float fluidSpacing);

// Whether particle k of `points` belongs to a selection (pins and parts; springs use both ends).
bool selected(const Selection& selection, const BodyPoints& points, size_t k);

}  // namespace kurage::sim
