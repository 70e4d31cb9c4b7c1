// Particle state as structure-of-arrays. Every per-particle quantity is one contiguous array so
// hot loops stream through memory; the neighbour grid keeps the arrays sorted by cell.
//
// Units: positions m, velocities m/s, accelerations m/s^2, densities kg/m^3, pressures Pa,
// masses kg. `kind` is 0 for fluid and k >= 1 for the k-th body; `id` is stable for the run.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace kurage::sim {

// What a pressure solver that solves for body particles' density must know of them, per particle
// (BodySystem::markUnsolved, SolverContext::unsolved): a pin holds it in place, its telescopic
// body has been stretched past what the model covers (sim/bodies.h), or its body is coupled as
// the fluid's boundary (BodyCoupling::Boundary).
enum UnsolvedState : uint8_t { kSolved = 0, kHeld = 1, kTorn = 2, kBoundary = 3 };

struct ParticleSet {
  std::vector<float> x, y, z;
  std::vector<float> vx, vy, vz;
  std::vector<float> ax, ay, az;
  std::vector<float> density;      // rho_i (3)
  std::vector<float> pressure;     // p_i (4)
  std::vector<float> restDensity;  // rho0_i, the paper's "density threshold"
  std::vector<float> mass;
  std::vector<int64_t> id;
  std::vector<int32_t> kind;

  size_t size() const { return x.size(); }

  void reserve(size_t n);
  // Appends one particle at rest with the given rest density and mass.
  void add(float px, float py, float pz, float vxIn, float vyIn, float vzIn, float rho0, float m, int64_t particleId,
           int32_t particleKind);
  // Reorders every array so that new index k holds old index order[k]. `scratch` is reused
  // storage of the caller so that no allocation happens once sizes are stable.
  void permute(const std::vector<uint32_t>& order, ParticleSet& scratch);
  // Removes the particles whose flag is non-zero, keeping the order of the rest.
  void removeFlagged(const std::vector<uint8_t>& flags);
};

// Sum of m v^2 / 2 over every particle (fluid and bodies), J, summed in index order in double.
double kineticEnergy(const ParticleSet& particles);

}  // namespace kurage::sim
