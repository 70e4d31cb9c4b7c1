#include "pipeline/sim_frame.h"

#include "sim/simulation.h"

namespace kurage::pipeline {

std::vector<std::string> kindNames(const Scene& scene) {
  std::vector<std::string> names{"fluid"};
  for (const sim::BodyParams& b : scene.sim.bodies) names.push_back(b.name);
  return names;
}

ParticleFrame frameFromSimulation(const Scene& scene, const sim::Simulation& simulation, int frame) {
  const sim::ParticleSet& p = simulation.particles();
  const sim::BodySystem* bodies = simulation.bodies();
  ParticleFrame f;
  f.time = simulation.time();
  f.frame = frame;
  f.kindNames = kindNames(scene);
  f.px = p.x; f.py = p.y; f.pz = p.z;
  f.vx = p.vx; f.vy = p.vy; f.vz = p.vz;
  f.id = p.id;
  f.kind = p.kind;
  f.restDensityFactor.resize(p.size());
  const float fluidRestDensity = scene.sim.fluid.restDensity;
  for (size_t i = 0; i < p.size(); ++i)
    f.restDensityFactor[i] =
        p.restDensity[i] / (p.kind[i] == 0 || !bodies ? fluidRestDensity : bodies->initialRestDensity(p.id[i]));
  return f;
}

}  // namespace kurage::pipeline
