// The one conversion from a running simulation to a particle cache frame (ParticleFrame), used by
// the sim stage, `kurage still` and every other command that turns simulation state into a frame.
//   kindNames            "fluid", then each body's name in scene order (index = kind value)
//   restDensityFactor    rho0_i over the particle's rest density as built (the fluid's, or its body
//                        part's): L^dens (SPEC §3.3) for body particles, 1 for fluid at rest
#pragma once

#include "pipeline/io/particle_cache.h"
#include "pipeline/scene.h"

namespace kurage::sim {
class Simulation;
}

namespace kurage::pipeline {

// The names of a scene's particle kinds: "fluid", then bodies[k-1].name for kind k.
std::vector<std::string> kindNames(const Scene& scene);

// The simulation's current state as the cache frame with index `frame`.
ParticleFrame frameFromSimulation(const Scene& scene, const sim::Simulation& simulation, int frame);

}  // namespace kurage::pipeline
