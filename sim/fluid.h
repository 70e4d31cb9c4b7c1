// The SPH fluid terms of SPEC §1, after Mueller et al. 2003, over a cell-sorted ParticleSet.
// Every particle (fluid or body) takes part in these sums: the paper's weak coupling.
// Each particle's sum runs over its candidates in a fixed order, so the result does not depend
// on the number of threads.
#pragma once

#include "sim/boundary.h"
#include "sim/kernels.h"
#include "sim/neighbor_grid.h"
#include "sim/params.h"
#include "sim/particles.h"

namespace kurage::sim {

// Box walls that take part in the SPH sums (wall weight functions), or none.
struct WallSums {
  const WallWeights* weights = nullptr;  // null: the paper's walls, no contribution
  ContainerParams box;
  float restDensity = 1000.0f;  // rho0 of the virtual wall particles
};

// (3) rho_i = sum_j m_j W_poly6(r_ij) (+ the walls' Z(d)), or with DensitySum::Volume
// rho_i = rho0_i sum_j (m_j / rho0_j) W_poly6(r_ij); also finds every particle's neighbours
// (|r_ij| < h).
// The kernel is poly6 (WCSPH, the paper) or the cubic spline (DFSPH). `boundaryVolume`, when not
// null, holds each particle's sum_b V_b W_ib over the walls' boundary particles: rho_i gains
// rho0_i times it (Akinci et al. 2012, boundary_particles.h).
void computeDensity(const NeighborGrid& grid, ParticleSet& particles, const Poly6Kernel& poly6,
                    NeighborLists& neighbors, const WallSums& walls, DensitySum form = DensitySum::Mass,
                    const float* boundaryVolume = nullptr);
void computeDensity(const NeighborGrid& grid, ParticleSet& particles, const CubicSplineKernel& cubic,
                    NeighborLists& neighbors, const WallSums& walls, DensitySum form = DensitySum::Mass,
                    const float* boundaryVolume = nullptr);

// (4) p_i = k_press (rho_i - rho0_i), clamped at zero when the scene asks for it (SPEC §8).
void computePressure(ParticleSet& particles, float pressureStiffness, NegativePressure negativePressure);

// (5) f_i^press = -sum_j m_j (p_i + p_j) / (2 rho_j) grad W_spiky(r_i - r_j)   (Mueller2003)
//     or -rho_i sum_j m_j (p_i / rho_i^2 + p_j / rho_j^2) grad W_spiky          (Monaghan1992)
// (6) f_i^vis   = mu sum_j m_j (v_j - v_i) / rho_j lap W_visc(|r_ij|),  mu = rho0 nu
// writes a_i = (f_i^press + f_i^vis) / rho_i + gravity  (force densities divided by density).
// Two particles at the same position push each other apart along +-x, ordered by id, so the
// result stays finite and symmetric. With `pressure` false only viscosity and gravity are added
// (a solver that corrects velocities itself, DFSPH). `boundaryGradient`, when not null, holds each
// particle's sum_b V_b grad W_spiky over the walls' boundary particles; the walls then push with
// the particle's own pressure extrapolated hydrostatically (p_b = p_i + rho0_i g . (x_b - x_i),
// rho_b = rho0_i; Akinci et al. 2012 with Adami, Hu & Adams 2012's wall pressure); `boundaryLift`
// holds each particle's sum_b V_b (g . (x_b - x_i)) grad W_spiky for that second part.
void computeFluidAcceleration(const NeighborLists& neighbors, ParticleSet& particles, const SpikyKernel& spiky,
                              const ViscosityKernel& viscosity, float dynamicViscosity,
                              const Eigen::Vector3f& gravity, PressureForce form, const WallSums& walls,
                              const float* correction = nullptr, bool pressure = true,
                              const float* boundaryGradient = nullptr, const float* boundaryLift = nullptr);

// Per-particle kernel gradient correction matrices (symmetric 3x3, stored as xx, yy, zz, xy, xz,
// yz per particle): L_i = M_i^-1 with M_i = sum_j V_j (-dW_spiky/dr / r) d d^T, d = r_i - r_j,
// V_j = m_j / rho_j. The identity for particles within h of a container wall or whose M_i is
// far from the identity (det < 0.25: a free surface or a sparse neighbourhood).
void computeGradientCorrection(const NeighborLists& neighbors, const ParticleSet& particles, const SpikyKernel& spiky,
                               const ContainerParams& box, std::vector<float>& correction);

// Mass that gives a particle deep inside a cubic lattice of the given spacing exactly the
// rest density with the poly6 kernel (SPEC §1, our calibration): m = rho0 / sum_j W(r_j).
float calibratedParticleMass(float spacing, float supportRadius, float restDensity,
                             DensityKernel kernel = DensityKernel::Poly6);

}  // namespace kurage::sim
