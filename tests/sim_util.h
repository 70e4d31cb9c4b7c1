// Helpers shared by the simulation tests: a particle set's kinetic energy and a plain box body.
#pragma once

#include "sim/params.h"
#include "sim/particles.h"

#include <Eigen/Core>

namespace kurage::test {

// Sum of m v^2 / 2 over every particle, J.
inline double kineticEnergy(const sim::ParticleSet& p) {
  double e = 0.0;
  for (size_t i = 0; i < p.size(); ++i) e += 0.5 * p.mass[i] * (p.vx[i] * p.vx[i] + p.vy[i] * p.vy[i] + p.vz[i] * p.vz[i]);
  return e;
}

// A box-shaped body named "box" over [min, max], every other parameter at its default.
inline sim::BodyParams boxBody(const Eigen::Vector3f& min, const Eigen::Vector3f& max) {
  sim::BodyParams b;
  b.name = "box";
  b.shape = sim::BodyShape::Box;
  b.min = min;
  b.max = max;
  return b;
}

}  // namespace kurage::test
