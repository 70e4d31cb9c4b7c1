// Helpers shared by the simulation tests: a particle set's kinetic energy, its positions by id,
// a plain box body and DFSPH's statistics.
#pragma once

#include "sim/params.h"
#include "sim/particles.h"
#include "sim/simulation.h"
#include "sim/solvers/dfsph/dfsph.h"

#include <Eigen/Core>

#include <algorithm>
#include <array>
#include <vector>

namespace kurage::test {

// Sum of m v^2 / 2 over every particle, J.
inline double kineticEnergy(const sim::ParticleSet& p) {
  double e = 0.0;
  for (size_t i = 0; i < p.size(); ++i) e += 0.5 * p.mass[i] * (p.vx[i] * p.vx[i] + p.vy[i] * p.vy[i] + p.vz[i] * p.vz[i]);
  return e;
}

// (id, x, y, z) of every particle, sorted by id: two runs compared whatever their particles' order.
inline std::vector<std::array<float, 4>> positionsById(const sim::ParticleSet& p) {
  std::vector<std::array<float, 4>> out;
  for (size_t i = 0; i < p.size(); ++i) out.push_back({float(p.id[i]), p.x[i], p.y[i], p.z[i]});
  std::sort(out.begin(), out.end());
  return out;
}

// The statistics of a simulation run by DFSPH.
inline const sim::DfsphStats& dfsphStats(const sim::Simulation& s) {
  return dynamic_cast<const sim::DfsphSolver&>(s.solver()).stats();
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
