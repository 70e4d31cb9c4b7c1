// One simulation: particles, neighbour grid and parameters, advanced in the paper's step order
// (SPEC §4). Owns all of its state; several simulations can live in one process.
//
// A step (written once, in step() and advanceTo()), in phases (StepPhase; the paper's numbers):
// 1-2 sort into buckets, the walls' sums (boundary particles; the wall weights' tables when the
// solver needs them), 4-5 rest density of telescopic bodies, 3 density, 6 pressure (the pressure
// solver's afterDensity), 7-8 pressure (when the solver asks for a pressure force) and viscosity
// forces, 9 springs (and muscles), 10 gravity, 11 acceleration, 12 v += a dt, the solver's
// velocity correction (when it makes one), 13 x += v dt (symplectic Euler), pins, 14 the bodies'
// collision loop, 15 walls; then emitters add and sinks remove fluid particles. A phase runs only
// when the scene needs it (no bodies: no body phase; no muscles: no muscle phase; ...) and its
// time is recorded. The pressure solver (sim/solvers/) is asked what it needs (StepNeeds), never
// which one it is.
#pragma once

#include "sim/bodies.h"
#include "sim/boundary.h"
#include "sim/boundary_particles.h"
#include "sim/emitter.h"
#include "sim/fluid.h"
#include "sim/kernels.h"
#include "sim/neighbor_grid.h"
#include "sim/params.h"
#include "sim/particles.h"
#include "sim/solvers/pressure_solver.h"
#include "sim/state.h"
#include "sim/time_step.h"

#include <array>
#include <memory>
#include <cstdint>
#include <stdexcept>
#include <string>

namespace kurage::sim {

// Thrown when the simulation cannot go on (a non-finite value, a step below the floor).
class SimulationError : public std::runtime_error {
public:
  using std::runtime_error::runtime_error;
};

// Thrown by advanceTo when a stop check (setStopChecks) asked it to end. Unless cutShort(), the
// state is that at the end of a whole step, and a checkpoint of it continues bit for bit; cut
// short, the last step's solve was ended early and the state is only fit to be thrown away.
class Stopped : public std::runtime_error {
public:
  Stopped(const std::string& what, bool cutShort) : std::runtime_error(what), cutShort_(cutShort) {}
  bool cutShort() const { return cutShort_; }

private:
  bool cutShort_;
};

// The parts of one time step, timed apart (run.json's stages.sim.step_phases). Not the pipeline's
// stages (sim, surface, render, export).
enum class StepPhase {
  Sort, Boundary, Density, TelescopicDensity, Pressure, Forces, Springs, Muscles, Integrate, DensitySolve, Pins,
  Collisions, Walls, Emitters, Sinks, Count
};
std::string_view phaseName(StepPhase phase);

struct SimStats {
  uint64_t steps = 0;
  double minStep = 0.0;
  double maxStep = 0.0;
  std::array<uint64_t, size_t(StepBound::Count)> boundCounts{};
  std::array<double, size_t(StepPhase::Count)> phaseSeconds{};  // wall time per phase
  std::array<uint64_t, size_t(StepPhase::Count)> phaseCalls{};    // times each phase ran
  uint64_t emitted = 0;         // particles spawned by emitters
  uint64_t emitterBlocked = 0;  // emitter positions skipped because a particle was there
  uint64_t removed = 0;         // particles removed by sinks
  // Compression of the fluid measured by each step's density pass: the mean over fluid particles
  // of max(rho_i - rho0_i, 0) / rho0_i (the error incompressible solvers bound), summed over steps,
  // and its largest.
  double densityErrorSum = 0.0;
  double densityErrorMax = 0.0;
  bool phaseRan(StepPhase s) const { return phaseCalls[size_t(s)] > 0; }
};

class Simulation {
public:
  // Builds the initial particles from the parameters (fluid blocks on a lattice) and calibrates
  // the particle mass. Throws std::invalid_argument for parameters the loader should have refused.
  explicit Simulation(SimParams params);

  const SimParams& params() const { return params_; }
  const ParticleSet& particles() const { return particles_; }
  ParticleSet& particles() { return particles_; }
  double time() const { return time_; }
  const SimStats& stats() const { return stats_; }
  const std::vector<Emitter>& emitters() const { return emitters_; }
  float fluidParticleMass() const { return fluidMass_; }
  // The telescopic bodies, or null for a scene without bodies.
  const BodySystem* bodies() const { return bodies_.get(); }
  // Neighbours found by the last density pass (mean count = totalCount / particles).
  const NeighborLists& neighbors() const { return neighbors_; }
  // The pressure solver (fluid.solver) and its iteration statistics.
  const PressureSolver& solver() const { return *solver_; }
  // The walls' boundary particles, or null (container.wall_density other than "boundary_particles").
  const BoundaryParticles* boundaryParticles() const { return boundary_.get(); }

  // Advances until time() == t exactly (the last step is shortened, and a step that would leave
  // a sliver is split in two halves). Throws SimulationError on a non-finite state.
  void advanceTo(double t);

  // So that a signal ends a run whatever its step count or step cost: `afterStep` is asked after
  // every step, and true makes advanceTo throw Stopped with a whole step's state; `inSolve` is
  // asked in every iteration of the pressure solves, and true ends the solve and, after that
  // step, throws Stopped cut short. Empty checks are never asked.
  void setStopChecks(StopCheck afterStep, StopCheck inSolve = {}) {
    stopAfterStep_ = std::move(afterStep);
    stopInSolve_ = std::move(inSolve);
  }

  // One step of the given size (no adaptivity); used by tests.
  void step(float dt);

  // The step the adaptive controller (or the fixed step) would take now.
  StepLimit nextStepLimit() const;

  // Bytes held by the simulation's per-particle arrays (particles, scratch, grid, neighbour lists).
  size_t memoryBytes() const;

  // Checkpoints: everything the run carries from step to step (the particles in their current
  // order, time, last step, ids, statistics, the solver's, bodies' and emitters' state). A
  // Simulation built from the same parameters and given this state continues bit for bit as the
  // one that saved it. restoreState throws StateError for state that does not fit the scene.
  void saveState(StateWriter& out) const;
  void restoreState(StateReader& in);

  // The stability bound of the scene's parameters at rest.
  StepLimit stabilityLimit() const;

private:
  void sortParticles();
  void computeBoundaryTerms();
  // Wall weights under a solver that needs the walls' sums: boundaryGradient_ and boundaryLift_
  // from the walls' tables.
  void computeWallWeightGradient();
  bool wallWeightTerms() const { return wallWeights_ && needs_.wallSums; }
  // fluid.gradient_correction under a solver that pushes in its own solves (StepNeeds): its L_i
  // in correction_, computed before the solver's first pass and handed to it in the context.
  bool solverCorrectsGradient() const { return params_.fluid.gradientCorrection && needs_.gradientCorrection; }
  void measureDensityError();
  void computeAccelerations();
  SolverContext solverContext();
  void addBodyForces(float dt);
  void integrate(float dt, double newTime);

  SimParams params_;
  ParticleSet particles_;
  ParticleSet scratch_;
  NeighborGrid grid_;
  NeighborLists neighbors_;
  std::vector<uint32_t> order_;
  Poly6Kernel poly6_;
  SpikyKernel spiky_;
  ViscosityKernel viscosity_;
  CubicSplineKernel cubic_;
  std::unique_ptr<PressureSolver> solver_;
  StepNeeds needs_;  // solver_->needs()
  std::unique_ptr<BoundaryParticles> boundary_;
  std::vector<float> boundaryVolume_;    // per particle: sum_b V_b W_ib (density kernel)
  std::vector<float> boundaryGradient_;  // per particle, 3 floats: sum_b V_b grad W_ib (solver's gradient)
  std::vector<float> boundaryLift_;      // per particle, 3 floats: sum_b V_b (g . (x_b - x_i)) grad W_ib
  // (both also from the wall weights, when the solver needs them: computeWallWeightGradient)
  float lastStep_ = 0.0f;
  StopCheck stopAfterStep_, stopInSolve_;
  bool solveCutShort_ = false;  // this step's solve was ended by stopInSolve_
  std::vector<double> errorPartial_;     // per chunk sums of measureDensityError()
  std::unique_ptr<WallWeights> wallWeights_;
  std::unique_ptr<BodySystem> bodies_;
  WallSums wallSums_;
  std::vector<float> correction_;  // kernel gradient correction, 6 floats per particle
  ViscosityLanes viscosityLanes_;  // the force pass's records on the solver's interleaved lists
  std::vector<uint8_t> unsolved_;  // per particle: held by a pin or torn this step (SolverContext::unsolved)
  BoundaryBodies boundaryBodies_;  // the bodies coupled as the fluid's boundary, this step's patches
  std::vector<Emitter> emitters_;
  std::vector<uint8_t> sinkFlags_;
  int64_t nextId_ = 0;
  float fluidMass_ = 0.0f;
  double time_ = 0.0;
  SimStats stats_;
};

}  // namespace kurage::sim
