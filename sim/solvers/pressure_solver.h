// The pressure solver seam: how the fluid's pressure is found each step. The step order itself
// is written once, in Simulation::step (sim/simulation.h); a solver plugs into it at two points:
//
//   sort, boundary terms, telescopic rest density, density (with the solver's kernel)
//   -> afterDensity():      WCSPH: p from the equation of state (4)
//                           DFSPH: its factors, then the divergence solve on v
//   -> non-pressure forces (viscosity, gravity; pressure too when pressureInForces()), springs,
//      muscles; v* = v + a dt
//   -> correctVelocities(): DFSPH: the constant-density solve on v*; WCSPH: nothing
//   -> x = x + v dt, pins, collisions, walls, emitters, sinks
//
// Adding a solver (IISPH, PCISPH, ...) means one file pair in this folder implementing
// PressureSolver and one line in registry.cpp's table; the scene key fluid.solver then accepts
// its name (docs/PHYSICS.md, "Pressure solvers").
#pragma once

#include "sim/kernels.h"
#include "sim/neighbor_grid.h"
#include "sim/params.h"
#include "sim/particles.h"
#include "sim/state.h"

#include <Eigen/Core>

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace kurage::sim {

// The bodies coupled as the fluid's boundary (BodyCoupling::Boundary; sim/solvers/dfsph.h), by
// sorted particle index (BodySystem::boundaryPatches; rebuilt after every sort).
struct BoundaryBodies {
  std::vector<uint8_t> sample;    // per particle: 1 for a particle of such a body (a held one too)
  std::vector<uint32_t> offsets;  // per particle + 1: particle i's patch is patch[offsets[i], offsets[i + 1])
  std::vector<uint32_t> patch;    // the particle itself and its spring neighbours (empty for others)
  std::vector<float> share;       // per particle: m_i over the sum of its patch's masses
  bool empty() const { return patch.empty(); }
};

// What a solver sees of the step: the sorted particles, their neighbours (found by the density
// pass, |r_ij| < h) and the walls' sums: from boundary particles, or, for an incompressible
// solver, from the wall weights' tables (null when the walls have neither).
struct SolverContext {
  ParticleSet& particles;
  const NeighborLists& neighbors;
  const FluidParams& fluid;
  float supportRadius = 1.0f;                 // h, m
  const float* boundaryVolume = nullptr;      // per particle: sum_b V_b W_ib (density kernel)
  const float* boundaryGradient = nullptr;    // per particle, 3 floats: sum_b V_b grad W_ib
  const float* boundaryLift = nullptr;        // per particle, 3 floats: sum_b V_b (g . (x_b - x_i)) grad W_ib
  const float* gradientCorrection = nullptr;  // per particle, 6 floats: L_i (fluid.h), or null
  // Per particle, an UnsolvedState (sim/particles.h): kHeld where a pin holds a body particle in
  // place this step (its velocity is not the solver's to change), kTorn where a telescopic body
  // is torn, kBoundary for a body coupled as the fluid's boundary; null when the bodies have
  // none of these.
  const uint8_t* unsolved = nullptr;
  const BoundaryBodies* boundaryBodies = nullptr;  // null when no body is coupled as a boundary
  float lastStep = 0.0f;                      // the previous step, s (0 before the first)
  Eigen::Vector3f gravity{0.0f, 0.0f, 0.0f};  // g, m/s^2
};

// Iteration statistics of the solvers that iterate (zero for WCSPH).
struct SolverStats {
  uint64_t steps = 0;                     // steps the solver ran
  uint64_t densityIterations = 0;         // summed over steps
  uint64_t divergenceIterations = 0;
  int maxDensityIterations = 0;           // largest in one step
  int maxDivergenceIterations = 0;
  uint64_t densityCapHits = 0;            // steps that stopped at the iteration cap
  uint64_t divergenceCapHits = 0;
  double lastDensityError = 0.0;          // the last step's final mean error, fraction of rho0
  double lastDivergenceError = 0.0;
  double maxDensityError = 0.0;           // largest final mean density error of any step
  double sumDensityError = 0.0;           // summed over steps (mean = sum / steps)
  uint64_t tornSteps = 0;                 // steps that left torn body particles out (SolverContext::unsolved)
  int maxTorn = 0;                        // most torn body particles left out in one step
};

class PressureSolver {
public:
  virtual ~PressureSolver() = default;
  virtual std::string_view name() const = 0;
  // The kernel of the density sum (3) and of the solver's own gradients.
  virtual DensityKernel densityKernel() const = 0;
  // True when the pressure force is a force term (WCSPH): Simulation adds -grad p / rho with the
  // other forces; false when the solver changes velocities itself.
  virtual bool pressureInForces() const = 0;
  // True for a solver without a speed of sound (the CFL bound then uses |v| and the spacing).
  virtual bool incompressible() const = 0;
  // True for a solver that couples bodies as the fluid's boundary (BodyCoupling::Boundary).
  virtual bool couplesBoundaryBodies() const { return false; }
  // After the density pass.
  virtual void afterDensity(const SolverContext& context) = 0;
  // After v* = v + a dt, before positions move.
  virtual void correctVelocities(const SolverContext& context, float dt) = 0;
  // A hydrostatic start's pressure as p_i / rho0_i^2 by particle id (0 for none), for a solver
  // that keeps pressure from step to step. WCSPH ignores it: its start is in the positions.
  virtual void setInitialPressure(const std::vector<float>& /*piById*/) {}
  virtual const SolverStats& stats() const = 0;
  virtual size_t memoryBytes() const { return 0; }
  // What the solver carries from step to step (its statistics, a warm start), for checkpoints.
  virtual void saveState(StateWriter& out) const { out.value(stats()); }
  virtual void restoreState(StateReader& in) { mutableStats() = in.value<SolverStats>(); }

protected:
  virtual SolverStats& mutableStats() = 0;
};

// The registry: names accepted by fluid.solver, and the solver of a scene's parameters.
const std::vector<std::string>& pressureSolverNames();
// Throws std::invalid_argument for a name not in pressureSolverNames().
std::unique_ptr<PressureSolver> makePressureSolver(const FluidParams& fluid);
// The density kernel of the scene's solver (for mass calibration before a solver exists).
DensityKernel densityKernelOf(const FluidParams& fluid);
// Why bodies cannot be coupled as the fluid's boundary (BodyCoupling::Boundary) under these fluid
// parameters, naming the key to change; empty when they can.
std::string boundaryCouplingProblem(const FluidParams& fluid);
// fluid.kernel with "auto" resolved: the solver's own kernel, but the cubic spline for WCSPH with
// boundary-particle walls (docs/PHYSICS.md, "Walls under WCSPH").
SphKernel resolvedKernel(const FluidParams& fluid, WallDensity walls);

}  // namespace kurage::sim
