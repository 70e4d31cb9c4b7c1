// Box walls.
//
// The paper's wall (SPEC §1, "Wall boundary"): after positions are updated, a particle that
// entered a wall is moved back onto it (zero distance). NoSlip (the paper) sets its velocity to
// zero; FreeSlip removes only the velocity component into the wall (SPEC §8).
//
// Optionally (container.wall_density = "wall_weight", our choice, docs/design/physics.md) walls also
// take part in the SPH sums through wall weight functions after Harada, Koshizuka & Kawaguchi,
// "Improvement of the boundary conditions in smoothed particle hydrodynamics", Computer Graphics
// & Geometry 9(3), 2007: behind each wall lies a virtual cubic lattice of particles continuing
// the fluid's initial lattice (first layer half a spacing behind the plane). Its density
// contribution Z(d) and the normal component of its summed kernel gradient G(d) depend only on
// the distance d of a particle from the plane (averaged over lateral offsets) and are tabulated
// once, with the fluid's own kernels (poly6 and spiky, or the cubic spline for both). The virtual
// particles carry the fluid's rest density and, mirror-like, the pressure of the particle they
// act on. Under DFSPH the tables also give the solver its wall terms, the sums boundary particles
// give (boundary_particles.h): sum_b V_b grad W_ib = -G(d) n / rho0 and the hydrostatic term
// (liftNormal below; Simulation::computeWallWeightGradient).
#pragma once

#include "sim/kernels.h"
#include "sim/params.h"
#include "sim/particles.h"

#include <algorithm>
#include <vector>

namespace kurage::sim {

// `inset` keeps particle centres that far inside the walls: 0 for the paper's walls, half a
// spacing with wall weights (a particle stands for a cube of one spacing, and the virtual
// lattice's first layer lies half a spacing behind the wall: a centre on the wall would sit
// half a spacing from it and count twice the density it should).
void enforceBoxWalls(ParticleSet& particles, const ContainerParams& container, float inset = 0.0f);

class WallWeights {
public:
  // Tabulated with the fluid's density kernel and its gradient partner (poly6 and spiky, or the
  // cubic spline for both), so that the walls continue the sums the fluid makes.
  WallWeights(float spacing, float supportRadius, float particleMass, DensityKernel kernel = DensityKernel::Poly6);

  // Sum over the virtual wall lattice of m W (the density kernel), for a particle at distance d in front of the
  // wall (d >= h gives 0; d < 0 is treated as 0).
  float density(float d) const { return lookup(density_, d); }
  // Normal component (pointing from the wall into the fluid) of -sum m grad W(r_i - r_j) (the
  // gradient kernel: spiky, or the cubic spline):
  // positive, so that pressure pushes the particle away from the wall.
  float gradient(float d) const { return lookup(gradient_, d); }

  // Where two perpendicular walls meet, their half-spaces overlap in a quarter-space that the
  // two face terms count twice: its density and its gradient components along each wall's
  // inward normal, for a particle at distances (d1, d2) from the two walls.
  struct Edge {
    float density = 0.0f, gradient1 = 0.0f, gradient2 = 0.0f;
  };
  Edge edge(float d1, float d2) const;

  // The walls' hydrostatic term for DFSPH (boundary_particles.h: sum_b m (g . (x_b - x)) grad W_ib
  // over the virtual lattice, Adami et al. 2012): for gravity g, a wall of inward normal n and a
  // particle at distance d it is -(g . n) A(d) n - B(d) (g - (g . n) n), with
  // A(d) = sum m W'(r)/r s^2 and B(d) = sum m W'(r)/r |t|^2 / 2 (s the normal and t the lateral
  // separation; the terms odd in t vanish in the lateral average).
  float liftNormal(float d) const { return lookup(liftNormal_, d); }
  float liftTangential(float d) const { return lookup(liftTangential_, d); }

private:
  float lookup(const std::vector<float>& table, float d) const;
  float h_;
  float step_;
  std::vector<float> density_, gradient_, liftNormal_, liftTangential_;
  int edgeSamples_ = 0;
  float edgeStep_ = 0.0f;
  std::vector<Edge> edge_;  // edgeSamples_^2, index i1 * edgeSamples_ + i2
};

// The walls of a box container seen by one particle: density contribution and the (unit-mass
// free) pressure direction terms summed over the six walls.
struct WallContribution {
  float density = 0.0f;
  Eigen::Vector3f gradient = Eigen::Vector3f::Zero();  // sum over walls of G(d) * inward normal
};

// Faces minus the edges where two walls are both within reach (inclusion-exclusion; the octant
// behind three walls at a box corner is left out, a small undercount at the eight corners only).
inline WallContribution boxWallContribution(const WallWeights& weights, const ContainerParams& box, float h, float x,
                                            float y, float z) {
  WallContribution c;
  const float p[3] = {x, y, z};
  float d[3];       // distance to the nearer wall on each axis
  float sign[3];    // inward normal of that wall along the axis
  bool near[3];
  for (int a = 0; a < 3; ++a) {
    const float dLow = p[a] - box.min[a], dHigh = box.max[a] - p[a];
    if (dLow < h) {
      c.density += weights.density(dLow);
      c.gradient[a] += weights.gradient(dLow);
    }
    if (dHigh < h) {
      c.density += weights.density(dHigh);
      c.gradient[a] -= weights.gradient(dHigh);
    }
    d[a] = std::min(dLow, dHigh);
    sign[a] = dLow <= dHigh ? 1.0f : -1.0f;
    near[a] = d[a] < h;
  }
  for (int a = 0; a < 3; ++a)
    for (int b = a + 1; b < 3; ++b) {
      if (!near[a] || !near[b]) continue;
      const WallWeights::Edge e = weights.edge(d[a], d[b]);
      c.density -= e.density;
      c.gradient[a] -= sign[a] * e.gradient1;
      c.gradient[b] -= sign[b] * e.gradient2;
    }
  return c;
}

// The walls' hydrostatic term (WallWeights::liftNormal) summed over the walls within reach,
// weighted by the virtual particles' mass m as the tables are (divide by rho0 for the volumes
// V_b = m / rho0 boundary particles carry); the edges' double count is not removed: a small
// overcount within h of an edge.
inline Eigen::Vector3f boxWallLift(const WallWeights& weights, const ContainerParams& box, float h,
                                   const Eigen::Vector3f& x, const Eigen::Vector3f& g) {
  Eigen::Vector3f lift = Eigen::Vector3f::Zero();
  for (int a = 0; a < 3; ++a)
    for (const float side : {1.0f, -1.0f}) {
      const float d = side > 0.0f ? x[a] - box.min[a] : box.max[a] - x[a];
      if (d >= h) continue;
      Eigen::Vector3f n = Eigen::Vector3f::Zero();
      n[a] = side;  // inward
      const float gn = g.dot(n);
      lift -= gn * weights.liftNormal(d) * n + weights.liftTangential(d) * (g - gn * n);
    }
  return lift;
}

}  // namespace kurage::sim
