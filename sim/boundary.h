// Box walls (SPEC §1, "Wall boundary"): after positions are updated, a particle that entered a
// wall is moved back onto it (zero distance). NoSlip (the paper) sets its velocity to zero;
// FreeSlip removes only the velocity component into the wall (SPEC §8).
#pragma once

#include "sim/params.h"
#include "sim/particles.h"

namespace kurage::sim {

void enforceBoxWalls(ParticleSet& particles, const ContainerParams& container);

}  // namespace kurage::sim
