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
#include "sim/solvers/sweeps.h"

namespace kurage::sim {

// Box walls that take part in the SPH sums (wall weight functions), or none.
struct WallSums {
  const WallWeights* weights = nullptr;  // null: the paper's walls, no contribution
  ContainerParams box;
  float restDensity = 1000.0f;  // rho0 of the virtual wall particles
  // Boundary particles under WCSPH (docs/design/physics.md, "Walls under WCSPH"): a fluid particle nearer
  // than penaltyRest to a wall plane of `box` is pushed back with penaltyStiffness (penaltyRest - d)
  // per unit mass (0: no push).
  float penaltyStiffness = 0.0f;  // 1/s^2
  float penaltyRest = 0.0f;       // m
};

// (3) rho_i = sum_j m_j W_poly6(r_ij) (+ the walls' Z(d)), or with DensitySum::Volume
// rho_i = rho0_i sum_j (m_j / rho0_j) W_poly6(r_ij); also finds every particle's neighbours
// (|r_ij| < h).
// The kernel is poly6 (the paper's, WCSPH's by default) or the cubic spline (DFSPH; fluid.kernel). `boundaryVolume`, when not
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

// The kernel of the pressure gradient: the paper's spiky (5), or the cubic spline of the density
// sum (fluid.kernel "cubic_spline"), with which the pressure force is the gradient of the
// density's potential energy.
struct GradientKernel {
  const SpikyKernel* spiky = nullptr;
  const CubicSplineKernel* cubic = nullptr;  // used when not null
};

// (5) f_i^press = -sum_j m_j (p_i + p_j) / (2 rho_j) grad W(r_i - r_j)   (Mueller2003)
//     or -rho_i sum_j m_j (p_i / rho_i^2 + p_j / rho_j^2) grad W          (Monaghan1992)
// (6) f_i^vis   = mu sum_j m_j (v_j - v_i) / rho_j lap W_visc(|r_ij|),  mu = rho0 nu
// writes a_i = (f_i^press + f_i^vis) / rho_i + gravity  (force densities divided by density).
// With the spiky gradient two particles at the same position push each other apart along +-x,
// ordered by id, so the result stays finite and symmetric (the cubic spline's gradient vanishes
// there). With `pressure` false only viscosity and gravity are added (a solver that corrects
// velocities itself, DFSPH). `boundaryGradient`, when not null, holds each
// particle's sum_b V_b grad W over the walls' boundary particles. A body particle is pushed by the
// walls with its own pressure mirrored (p_b = p_i, rho_b = rho0_i; Akinci et al. 2012); a fluid
// particle by the part of that push that is the gradient of its density's energy (p_b = 0: the
// walls' term of -rho_i (p_i / rho_i^2) grad rho_i) and by the walls' penalty in `walls`
// (docs/design/physics.md, "Walls under WCSPH": the mirrored push fed energy into a still tank).
// With `pressure` false and lanes->lists set (the solver's interleaved lists of this step), the
// viscosity is summed eight particles at a time on them (solvers/sweeps.h's lanes path: the same floats).
struct ViscosityLanes {
  const solvers::LaneLists* lists = nullptr;
  std::vector<solvers::Float4> x, v;  // per particle (x, y, z, m / rho) and (vx, vy, vz, 0), kept between steps
};
void computeFluidAcceleration(const NeighborLists& neighbors, ParticleSet& particles, GradientKernel kernel,
                              const ViscosityKernel& viscosity, float dynamicViscosity,
                              const Eigen::Vector3f& gravity, PressureForce form, const WallSums& walls,
                              const float* correction = nullptr, bool pressure = true,
                              const float* boundaryGradient = nullptr, ViscosityLanes* lanes = nullptr);

// Per-particle kernel gradient correction matrices (symmetric 3x3, stored as xx, yy, zz, xy, xz,
// yz per particle): L_i = M_i^-1 with M_i = sum_j V_j (-dW/dr / r) d d^T, d = r_i - r_j,
// V_j = m_j / rho_j, W the pressure gradient's kernel. The identity for particles within h of a
// container wall or whose M_i is far from the identity (det < 0.25: a free surface or a sparse
// neighbourhood). With kernel.cubic it reads W'(r)/r from `neighbors`' slopes, so this step's
// density pass must have been the cubic spline's (it fills them).
void computeGradientCorrection(const NeighborLists& neighbors, const ParticleSet& particles, GradientKernel kernel,
                               const ContainerParams& box, std::vector<float>& correction);

// Mass that gives a particle deep inside a cubic lattice of the given spacing exactly the
// rest density with the poly6 kernel (SPEC §1, our calibration): m = rho0 / sum_j W(r_j).
float calibratedParticleMass(float spacing, float supportRadius, float restDensity,
                             DensityKernel kernel = DensityKernel::Poly6);

}  // namespace kurage::sim
