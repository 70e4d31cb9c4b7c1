#include "sim/simulation.h"

#include "sim/boundary.h"
#include "sim/fluid.h"
#include "sim/packing.h"
#include "sim/setup.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <limits>
#include <chrono>
#include <cmath>
#include <sstream>

namespace kurage::sim {

std::string_view phaseName(StepPhase phase) {
  switch (phase) {
    case StepPhase::Sort: return "neighbour_sort";
    case StepPhase::Boundary: return "wall_sums";
    case StepPhase::DensitySolve: return "density_solve";
    case StepPhase::Density: return "density";
    case StepPhase::TelescopicDensity: return "telescopic_density";
    case StepPhase::Pressure: return "pressure";
    case StepPhase::Forces: return "pressure_viscosity_forces";
    case StepPhase::Springs: return "springs";
    case StepPhase::Muscles: return "muscles";
    case StepPhase::Integrate: return "integrate";
    case StepPhase::Pins: return "pins";
    case StepPhase::Collisions: return "collisions";
    case StepPhase::Walls: return "walls";
    case StepPhase::Emitters: return "emitters";
    case StepPhase::Sinks: return "sinks";
    case StepPhase::Count: break;
  }
  return "?";
}

namespace {
class PhaseTimer {
public:
  PhaseTimer(SimStats& stats, StepPhase phase) : stats_(stats), phase_(phase), start_(std::chrono::steady_clock::now()) {}
  ~PhaseTimer() {
    ++stats_.phaseCalls[size_t(phase_)];
    stats_.phaseSeconds[size_t(phase_)] +=
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  }
private:
  SimStats& stats_;
  StepPhase phase_;
  std::chrono::steady_clock::time_point start_;
};

// Largest value of f(i) over all particles; max is exact, so the result is deterministic.
template <class F>
float maxOver(size_t count, F&& f) {
  return tbb::parallel_reduce(
      tbb::blocked_range<size_t>(0, count, 4096), 0.0f,
      [&](const tbb::blocked_range<size_t>& r, float m) {
        for (size_t i = r.begin(); i != r.end(); ++i) m = std::max(m, f(i));
        return m;
      },
      [](float a, float b) { return std::max(a, b); });
}
// Bodies displace the fluid they start in: lattice points of the fluid blocks closer than
// (l + d_body) / 2 to a body particle are not created.
void removeDisplacedFluid(const ParticleSet& p, float spacing, const std::vector<BodyParams>& bodies,
                          std::vector<std::vector<Eigen::Vector3f>>& blocks) {
  float largest = 0.0f;
  for (const BodyParams& b : bodies) largest = std::max(largest, b.spacingMetres(spacing));
  const float clearance = 0.5f * (spacing + largest) * 0.999f;
  const float cell = clearance;
  auto coord = [cell](float v) { return int64_t(std::floor(v / cell)); };
  auto key = [](int64_t cx, int64_t cy, int64_t cz) {
    return uint64_t(cx & 0x1FFFFF) << 42 | uint64_t(cy & 0x1FFFFF) << 21 | uint64_t(cz & 0x1FFFFF);
  };
  std::vector<std::pair<uint64_t, uint32_t>> cells;
  for (size_t i = 0; i < p.size(); ++i) cells.emplace_back(key(coord(p.x[i]), coord(p.y[i]), coord(p.z[i])), uint32_t(i));
  std::sort(cells.begin(), cells.end());
  for (std::vector<Eigen::Vector3f>& points : blocks)
    std::erase_if(points, [&](const Eigen::Vector3f& q) {
      for (int dz = -1; dz <= 1; ++dz)
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            const uint64_t k = key(coord(q.x()) + dx, coord(q.y()) + dy, coord(q.z()) + dz);
            for (auto it = std::lower_bound(cells.begin(), cells.end(), std::make_pair(k, uint32_t(0)));
                 it != cells.end() && it->first == k; ++it) {
              const size_t i = it->second;
              const float ddx = p.x[i] - q.x(), ddy = p.y[i] - q.y(), ddz = p.z[i] - q.z();
              if (ddx * ddx + ddy * ddy + ddz * ddz < clearance * clearance) return true;
            }
          }
      return false;
    });
}
}  // namespace

Simulation::Simulation(SimParams params)
    : params_(std::move(params)),
      poly6_(params_.fluid.supportRadiusMetres()),
      spiky_(params_.fluid.supportRadiusMetres()),
      viscosity_(params_.fluid.supportRadiusMetres()),
      cubic_(params_.fluid.supportRadiusMetres()) {
  const FluidParams& fluid = params_.fluid;
  if (!(fluid.spacing > 0.0f) || !(fluid.supportRadius > 0.0f) || !(fluid.restDensity > 0.0f))
    throw std::invalid_argument("simulation: spacing, support radius and rest density must be > 0");
  params_.fluid.kernel = resolvedKernel(params_.fluid, params_.container.wallDensity);
  solver_ = makePressureSolver(fluid);
  needs_ = solver_->needs();
  grid_.configure(params_.container.min, params_.container.max, fluid.supportRadiusMetres());
  // fluid.packing "relaxed": blocks that hold a tile start on it (sim/packing.h), and the fluid's
  // mass is calibrated on it (thinner blocks start on the lattice with that mass). The walls'
  // samples stay on the lattice, with the lattice's calibration.
  const float latticeMass = calibratedParticleMass(fluid.spacing, fluid.supportRadiusMetres(), fluid.restDensity,
                                                   solver_->densityKernel());
  const bool relaxed = fluid.packing == StartPacking::Relaxed;
  if (relaxed && solver_->densityKernel() != DensityKernel::CubicSpline)
    throw std::invalid_argument("fluid.packing: 'relaxed' needs the cubic-spline density kernel");
  const PackingTile tile = relaxed ? relaxedTile(fluid.supportRadius, solver_->densityKernel()) : PackingTile{};
  fluidMass_ = relaxed ? tileParticleMass(tile, fluid.spacing, fluid.restDensity) : latticeMass;
  if (params_.container.wallDensity == WallDensity::BoundaryParticles)
    boundary_ = std::make_unique<BoundaryParticles>(params_.container, fluid.spacing, fluid.supportRadiusMetres(),
                                                    latticeMass / fluid.restDensity);
  if (params_.container.wallDensity == WallDensity::WallWeight) {
    wallWeights_ = std::make_unique<WallWeights>(fluid.spacing, fluid.supportRadiusMetres(), latticeMass,
                                                 solver_->densityKernel());
    wallSums_.weights = wallWeights_.get();
  }
  wallSums_.box = params_.container;
  wallSums_.restDensity = fluid.restDensity;
  if (boundary_) {
    wallSums_.penaltyStiffness = needs_.wallPenaltyStiffness;
    wallSums_.penaltyRest = needs_.wallPenaltyRest;
  }
  std::vector<std::vector<Eigen::Vector3f>> blockPoints;
  size_t expected = 0;
  std::vector<bool> tiled;
  for (const FluidBlock& block : params_.fluidBlocks) {
    tiled.push_back(relaxed && holdsTile(block, fluid.spacing, fluid.supportRadius));
    blockPoints.push_back(tiled.back() ? tiledPoints(block, fluid.spacing, tile) : latticePoints(block, fluid.spacing));
    expected += blockPoints.back().size();
  }
  // Free surface of each block: its top lattice layer plus half a spacing (before any compression);
  // a tiled block's top (its points fill it to the top, the highest within a spacing of it).
  std::vector<float> tops;
  for (size_t b = 0; b < blockPoints.size(); ++b) {
    float top = -std::numeric_limits<float>::infinity();
    for (const Eigen::Vector3f& q : blockPoints[b]) top = std::max(top, q.z());
    tops.push_back(tiled[b] ? std::min(top + 0.5f * fluid.spacing, params_.fluidBlocks[b].max.z())
                            : top + 0.5f * fluid.spacing);
  }
  const float g = -params_.gravity.z();
  const bool hydrostatic = fluid.initialState == InitialState::Hydrostatic && g > 0.0f;
  if (hydrostatic) solver_->hydrostaticLattice(blockPoints, tops, g);
  for (const EmitterParams& e : params_.emitters) {
    emitters_.emplace_back(e, fluid.spacing);
    expected += emitters_.back().expectedTotal();
  }
  for (size_t b = 0; b < params_.bodies.size(); ++b)
    if (params_.bodies[b].coupling == BodyCoupling::Boundary)
      if (const std::string why = boundaryCouplingProblem(fluid); !why.empty())
        throw std::invalid_argument("bodies[" + std::to_string(b) + "].coupling: " + why);
  if (!params_.bodies.empty()) {
    bodies_ = std::make_unique<BodySystem>(params_, particles_, nextId_);  // body ids first
    removeDisplacedFluid(particles_, fluid.spacing, params_.bodies, blockPoints);
  }
  particles_.reserve(particles_.size() + expected);
  std::vector<float> headById;  // g depth, m^2/s^2 (PressureSolver::hydrostaticHead)
  for (size_t b = 0; b < blockPoints.size(); ++b)
    for (const Eigen::Vector3f& q : blockPoints[b]) {
      if (hydrostatic) {
        headById.resize(size_t(nextId_) + 1, 0.0f);
        headById[size_t(nextId_)] = g * std::max(tops[b] - q.z(), 0.0f);
      }
      particles_.add(q.x(), q.y(), q.z(), 0, 0, 0, fluid.restDensity, fluidMass_, nextId_++, 0);
    }
  if (!headById.empty()) solver_->hydrostaticHead(headById);
}

SolverContext Simulation::solverContext() {
  SolverContext c{particles_, neighbors_, params_.fluid};
  c.supportRadius = params_.fluid.supportRadiusMetres();
  if (boundary_) {
    c.boundaryVolume = boundaryVolume_.data();
    c.boundaryGradient = boundaryGradient_.data();
    c.boundaryLift = boundaryLift_.data();
  } else if (wallWeightTerms()) {
    c.boundaryGradient = boundaryGradient_.data();  // the wall weights' (computeWallWeightGradient)
    c.boundaryLift = boundaryLift_.data();
  }
  if (solverCorrectsGradient()) c.gradientCorrection = correction_.data();
  if (!unsolved_.empty()) c.unsolved = unsolved_.data();
  if (!boundaryBodies_.empty()) c.boundaryBodies = &boundaryBodies_;
  c.lastStep = lastStep_;
  c.gravity = params_.gravity;
  if (stopInSolve_) {
    c.stop = &stopInSolve_;
    c.cutShort = &solveCutShort_;
  }
  return c;
}

void Simulation::measureDensityError() {
  const ParticleSet& p = particles_;
  const size_t n = p.size();
  constexpr size_t kChunk = 4096;
  std::vector<double>& partial = errorPartial_;
  const size_t chunks = (n + kChunk - 1) / kChunk;
  partial.assign(2 * chunks, 0.0);
  tbb::parallel_for(size_t(0), chunks, [&](size_t c) {
    double sum = 0.0, count = 0.0;
    for (size_t i = c * kChunk; i < std::min(n, (c + 1) * kChunk); ++i)
      if (p.kind[i] == 0) {
        sum += std::max(p.density[i] - p.restDensity[i], 0.0f) / p.restDensity[i];
        count += 1.0;
      }
    partial[2 * c] = sum;
    partial[2 * c + 1] = count;
  });
  double sum = 0.0, count = 0.0;
  for (size_t c = 0; c < chunks; ++c) { sum += partial[2 * c]; count += partial[2 * c + 1]; }
  const double error = count > 0.0 ? sum / count : 0.0;
  stats_.densityErrorSum += error;
  stats_.densityErrorMax = std::max(stats_.densityErrorMax, error);
}

void Simulation::computeBoundaryTerms() {
  PhaseTimer timer(stats_, StepPhase::Boundary);
  const ParticleSet& p = particles_;
  const size_t n = p.size();
  boundaryVolume_.resize(n);
  boundaryGradient_.resize(3 * n);
  boundaryLift_.resize(3 * n);
  const Eigen::Vector3f gravity = params_.gravity;
  const bool cubic = solver_->densityKernel() == DensityKernel::CubicSpline;
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 2048), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) {
      Eigen::Vector3f grad, lift = Eigen::Vector3f::Zero();
      // The hydrostatic sum only for a solver that reads it (StepNeeds::wallSums)
      Eigen::Vector3f* hydrostatic = needs_.wallSums ? &lift : nullptr;
      if (cubic) boundary_->sums(cubic_, cubic_, p.x[i], p.y[i], p.z[i], boundaryVolume_[i], grad, &gravity, hydrostatic);
      else boundary_->sums(poly6_, spiky_, p.x[i], p.y[i], p.z[i], boundaryVolume_[i], grad, &gravity, hydrostatic);
      boundaryGradient_[3 * i] = grad.x(); boundaryGradient_[3 * i + 1] = grad.y(); boundaryGradient_[3 * i + 2] = grad.z();
      boundaryLift_[3 * i] = lift.x(); boundaryLift_[3 * i + 1] = lift.y(); boundaryLift_[3 * i + 2] = lift.z();
    }
  });
}

void Simulation::computeWallWeightGradient() {
  PhaseTimer timer(stats_, StepPhase::Boundary);
  const ParticleSet& p = particles_;
  const size_t n = p.size();
  boundaryGradient_.resize(3 * n);
  boundaryLift_.resize(3 * n);
  const float h = params_.fluid.supportRadiusMetres(), rho0 = params_.fluid.restDensity;
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 2048), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) {
      // The table's G(d) n is -sum_b m grad W_ib over the virtual wall lattice: sum_b V_b grad W_ib
      // with V_b = m / rho0, as boundary particles give it.
      // With density_sum "mass" the density pass adds the tables' Z(d), the fluid's rho0 times
      // sum_b V_b W, whatever the particle's own rest density; DFSPH weighs this term with rho0_i
      // (DfsphSolver::wallWeight), so it is scaled by rho0 / rho0_i to stay the density's rate
      // (1 for fluid particles).
      const float form = params_.fluid.densitySum == DensitySum::Mass ? rho0 / p.restDensity[i] : 1.0f;
      const Eigen::Vector3f g =
          -boxWallContribution(*wallWeights_, params_.container, h, p.x[i], p.y[i], p.z[i]).gradient * (form / rho0);
      boundaryGradient_[3 * i] = g.x(); boundaryGradient_[3 * i + 1] = g.y(); boundaryGradient_[3 * i + 2] = g.z();
      const Eigen::Vector3f lift =
          boxWallLift(*wallWeights_, params_.container, h, Eigen::Vector3f(p.x[i], p.y[i], p.z[i]), params_.gravity) / rho0;
      boundaryLift_[3 * i] = lift.x(); boundaryLift_[3 * i + 1] = lift.y(); boundaryLift_[3 * i + 2] = lift.z();
    }
  });
}

void Simulation::sortParticles() {
  PhaseTimer timer(stats_, StepPhase::Sort);
  grid_.sort(particles_.x.data(), particles_.y.data(), particles_.z.data(), particles_.size(), order_);
  particles_.permute(order_, scratch_);
}

void Simulation::computeAccelerations() {
  sortParticles();
  if (bodies_) bodies_->index(particles_);
  // (4)-(5) depend only on positions, so they run before (3): the volume-weighted density sum
  // needs the neighbours' rest densities of this step.
  if (bodies_ && bodies_->hasTelescopicDensity()) {
    PhaseTimer timer(stats_, StepPhase::TelescopicDensity);
    bodies_->updateRestDensity(particles_);
  }
  if (bodies_ && bodies_->mayLeaveParticlesUnsolved()) bodies_->markUnsolved(particles_, time_, unsolved_);  // for the solver
  if (bodies_ && bodies_->hasBoundaryBodies()) bodies_->boundaryPatches(particles_, boundaryBodies_);
  const float* boundaryVolume = nullptr;
  if (wallWeightTerms()) computeWallWeightGradient();
  if (boundary_) {
    computeBoundaryTerms();
    boundaryVolume = boundaryVolume_.data();
  }
  {
    PhaseTimer timer(stats_, StepPhase::Density);
    if (solver_->densityKernel() == DensityKernel::Poly6)
      computeDensity(grid_, particles_, poly6_, neighbors_, wallSums_, params_.fluid.densitySum, boundaryVolume);
    else
      computeDensity(grid_, particles_, cubic_, neighbors_, wallSums_, params_.fluid.densitySum, boundaryVolume);
  }
  measureDensityError();
  {
    PhaseTimer timer(stats_, StepPhase::Pressure);
    if (solverCorrectsGradient())
      computeGradientCorrection(neighbors_, particles_, GradientKernel{&spiky_, &cubic_}, params_.container, correction_);
    solver_->afterDensity(solverContext());  // (4), or DFSPH's factors and divergence solve, ...
  }
  {
    PhaseTimer timer(stats_, StepPhase::Forces);
    const float mu = params_.fluid.restDensity * params_.fluid.kinematicViscosity;  // mu = rho0 nu
    const bool pressure = needs_.pressureForce;
    const bool correct = pressure && params_.fluid.gradientCorrection &&
                         params_.fluid.pressureForce == PressureForce::Monaghan1992;
    const GradientKernel kernel{&spiky_, solver_->densityKernel() == DensityKernel::CubicSpline ? &cubic_ : nullptr};
    if (correct) computeGradientCorrection(neighbors_, particles_, kernel, params_.container, correction_);
    viscosityLanes_.lists = solver_->laneLists();
    computeFluidAcceleration(neighbors_, particles_, kernel, viscosity_, mu, params_.gravity,
                             params_.fluid.pressureForce, wallSums_, correct ? correction_.data() : nullptr, pressure,
                             boundary_ ? boundaryGradient_.data() : nullptr, &viscosityLanes_);
  }
}

void Simulation::addBodyForces(float dt) {
  if (!bodies_) return;
  if (bodies_->hasMuscles()) {
    PhaseTimer timer(stats_, StepPhase::Muscles);
    bodies_->addMuscleForces(particles_, time_);
  }
  {
    PhaseTimer timer(stats_, StepPhase::Springs);
    bodies_->addSpringForces(particles_, dt);  // (9), last: an implicit damper needs every other force
  }
}

void Simulation::integrate(float dt, double newTime) {
  {
    PhaseTimer timer(stats_, StepPhase::Integrate);
    ParticleSet& p = particles_;
    tbb::parallel_for(tbb::blocked_range<size_t>(0, p.size(), 4096), [&](const tbb::blocked_range<size_t>& r) {
      for (size_t i = r.begin(); i != r.end(); ++i) {
        p.vx[i] += p.ax[i] * dt; p.vy[i] += p.ay[i] * dt; p.vz[i] += p.az[i] * dt;  // (12) v* = v + a dt
      }
    });
  }
  if (needs_.correctsVelocities) {
    PhaseTimer timer(stats_, StepPhase::DensitySolve);
    solver_->correctVelocities(solverContext(), dt);  // v* made density-preserving (DFSPH, IISPH)
  }
  {
    PhaseTimer timer(stats_, StepPhase::Integrate);
    ParticleSet& p = particles_;
    tbb::parallel_for(tbb::blocked_range<size_t>(0, p.size(), 4096), [&](const tbb::blocked_range<size_t>& r) {
      for (size_t i = r.begin(); i != r.end(); ++i) {
        p.x[i] += p.vx[i] * dt; p.y[i] += p.vy[i] * dt; p.z[i] += p.vz[i] * dt;  // (13) x* = x + v* dt: symplectic Euler
      }
    });
  }
  if (bodies_ && bodies_->hasPins()) {
    PhaseTimer timer(stats_, StepPhase::Pins);
    bodies_->applyPins(particles_, newTime);
  }
  if (bodies_) {
    PhaseTimer timer(stats_, StepPhase::Collisions);
    bodies_->collide(particles_, params_.collisions.maxPasses, newTime);  // (14)
  }
  {
    PhaseTimer timer(stats_, StepPhase::Walls);
    enforceBoxWalls(particles_, params_.container, wallSums_.weights ? 0.5f * params_.fluid.spacing : 0.0f);  // (15)
  }
  time_ = newTime;
  lastStep_ = dt;
  if (!emitters_.empty()) {
    PhaseTimer timer(stats_, StepPhase::Emitters);
    for (Emitter& e : emitters_) {
      const uint64_t blockedBefore = e.blocked();
      stats_.emitted += e.emit(time_, dt, particles_, fluidMass_, params_.fluid.restDensity, nextId_);
      stats_.emitterBlocked += e.blocked() - blockedBefore;
    }
  }
  if (!params_.sinks.empty()) {
    PhaseTimer timer(stats_, StepPhase::Sinks);
    for (const SinkParams& sink : params_.sinks) stats_.removed += applySink(sink, particles_, sinkFlags_);
  }
  ++stats_.steps;
  if (stats_.steps == 1 || dt < stats_.minStep) stats_.minStep = dt;
  if (dt > stats_.maxStep) stats_.maxStep = dt;
}

void Simulation::step(float dt) {
  computeAccelerations();
  addBodyForces(dt);
  integrate(dt, time_ + dt);
}

namespace {
// The inputs of the adaptive bounds in the current state (speeds, and accelerations of this step).
// The CFL bound of the solver: h / (c + |v|) for WCSPH, l / |v| for an incompressible one.
void setCflInputs(StepInputs& in, const SimParams& params, const PressureSolver& solver) {
  in.supportRadius = params.fluid.supportRadiusMetres();
  in.speedOfSound = solver.incompressible() ? 0.0f : params.fluid.speedOfSound();
  in.cflLength = solver.incompressible() ? params.fluid.spacing : 0.0f;
}

// l / sqrt(|g| H) for an incompressible solver (time_step.h), H the fluid's extent along gravity: the
// hydrostatic pressure at its deepest point. (The largest particle pressure instead followed the
// solver's transients: a divergence correction's impulse over one step read 60 MPa in the
// jellyfish's bell and asked for a step below its floor.) 0 without gravity or fluid.
float pressureStep(const SimParams& params, const ParticleSet& p, const PressureSolver& solver) {
  const float g = params.gravity.norm();
  if (!solver.incompressible() || !(g > 0.0f)) return 0.0f;
  const Eigen::Vector3f down = params.gravity / g;
  using Range = std::pair<float, float>;  // the fluid's lowest and highest height along -g
  constexpr float inf = std::numeric_limits<float>::infinity();
  const Range range = tbb::parallel_reduce(
      tbb::blocked_range<size_t>(0, p.size(), 4096), Range{inf, -inf},
      [&](const tbb::blocked_range<size_t>& r, Range m) {
        for (size_t i = r.begin(); i != r.end(); ++i)
          if (p.kind[i] == 0) {
            const float up = -(down.x() * p.x[i] + down.y() * p.y[i] + down.z() * p.z[i]);
            m = {std::min(m.first, up), std::max(m.second, up)};
          }
        return m;
      },
      [](Range a, Range b) { return Range{std::min(a.first, b.first), std::max(a.second, b.second)}; });
  const float depth = range.second - range.first;
  return std::isfinite(depth) && depth > 0.0f ? params.fluid.spacing / std::sqrt(g * depth) : 0.0f;
}

StepInputs currentStepInputs(const SimParams& params, const ParticleSet& p, const BodySystem* bodies,
                             const PressureSolver& solver) {
  StepInputs in;
  setCflInputs(in, params, solver);
  in.kinematicViscosity = params.fluid.kinematicViscosity;
  in.maxSpeed = std::sqrt(maxOver(p.size(), [&](size_t i) {
    return p.vx[i] * p.vx[i] + p.vy[i] * p.vy[i] + p.vz[i] * p.vz[i];
  }));
  in.maxAcceleration = std::sqrt(maxOver(p.size(), [&](size_t i) {
    return p.ax[i] * p.ax[i] + p.ay[i] * p.ay[i] + p.az[i] * p.az[i];
  }));
  if (bodies) in.springStep = bodies->springStep();
  in.pressureStep = pressureStep(params, p, solver);
  return in;
}

// A fixed step above the stability limits of the current state stops the run. The limits are the
// adaptive bounds without their safety factors (time_step.*_factor: cfl 0.4, force 0.25, spring
// 0.5): a Courant number of 1, h / (c + |v|max); the explicit spring and damper limit
// min sqrt(2 m / K), m / D (a Gershgorin bound: exact for a chain, up to about 2 times too strict
// for a 3-D body with an implicit damper); sqrt(h / |a|max). The viscous bound keeps its default
// factor: 1.5 times 0.125 h^2 / nu already gains energy. Measured in docs/results/stability.md.
constexpr float kViscousLimitFactor = 0.125f;
// The pressure bound's edge: omega dt = 2 with the measured C ~ 6 (time_step.h), 2 / sqrt(6).
constexpr float kPressureLimitFactor = 0.8f;
}  // namespace

StepLimit Simulation::nextStepLimit() const {
  const TimeStepParams& ts = params_.timeStep;
  if (ts.mode == TimeStepMode::Fixed) return {ts.fixedStep, StepBound::Fixed};
  return adaptiveStep(ts, currentStepInputs(params_, particles_, bodies_.get(), *solver_));
}

StepLimit Simulation::stabilityLimit() const {
  StepInputs in;
  setCflInputs(in, params_, *solver_);
  in.kinematicViscosity = params_.fluid.kinematicViscosity;
  in.maxAcceleration = params_.gravity.norm();
  if (bodies_) in.springStep = bodies_->springStep();
  in.pressureStep = pressureStep(params_, particles_, *solver_);
  return stabilityBound(params_.timeStep, in);
}

size_t Simulation::memoryBytes() const {
  auto setBytes = [](const ParticleSet& p) {
    size_t b = 0;
    for (const auto* a : {&p.x, &p.y, &p.z, &p.vx, &p.vy, &p.vz, &p.ax, &p.ay, &p.az, &p.density, &p.pressure,
                          &p.restDensity, &p.mass})
      b += a->capacity() * sizeof(float);
    return b + p.id.capacity() * sizeof(int64_t) + p.kind.capacity() * sizeof(int32_t);
  };
  return setBytes(particles_) + setBytes(scratch_) + grid_.memoryBytes() + neighbors_.memoryBytes() +
         (boundaryLift_.capacity() + correction_.capacity()) * sizeof(float) +
         order_.capacity() * sizeof(uint32_t) + (bodies_ ? bodies_->memoryBytes() : 0) + solver_->memoryBytes() +
         (boundaryVolume_.capacity() + boundaryGradient_.capacity()) * sizeof(float) +
         (boundary_ ? boundary_->size() * 3 * sizeof(float) : 0) + unsolved_.capacity() +
         boundaryBodies_.sample.capacity() + (boundaryBodies_.offsets.capacity() + boundaryBodies_.patch.capacity()) * sizeof(uint32_t) +
         boundaryBodies_.share.capacity() * sizeof(float) +
         (viscosityLanes_.x.capacity() + viscosityLanes_.v.capacity()) * sizeof(solvers::Float4);
}

void Simulation::advanceTo(double t) {
  while (time_ < t) {
    // Under an incompressible solver a step far shorter than the last one kicks the fluid: its
    // density solve removes within that step the density error the last step left (up to the
    // tolerance), so the velocity it applies grows as 1 / dt, and the pressure it leaves
    // warm-starts the next, full step (measured on a still tank with 0.025 s steps: a last step of
    // 1 ms before t = 1 s took the RMS speed from 0.13 to 0.47 m/s, and to 1.9 m/s by 1.1 s; one
    // of 10 us, to 47 m/s; one of 0.1 us stopped the run). Steps this loop makes are at least
    // half the step limit; a request to advance by less than time_step.min_step, a sliver left by
    // a caller's rounding (a study sampling at float-rounded times), moves the clock without a step.
    if (solver_->incompressible() && t - time_ < double(params_.timeStep.minStep)) {
      time_ = t;
      break;
    }
    computeAccelerations();
    const StepLimit limit = nextStepLimit();
    if (!(limit.step >= params_.timeStep.minStep) && params_.timeStep.mode == TimeStepMode::Adaptive) {
      std::ostringstream msg;
      msg << "time " << time_ << " s: the " << stepBoundName(limit.bound) << " bound asks for a step of "
          << limit.step << " s, below the floor time_step.min_step = " << params_.timeStep.minStep << " s";
      throw SimulationError(msg.str());
    }
    if (params_.timeStep.mode == TimeStepMode::Fixed) {
      // A fixed step far above the stability bounds does not always end in a non-finite value:
      // the walls put escaping particles back and stop them, so the state can stay finite while
      // its energy grows 3 to 2500 times over (tests/test_stability.cpp, TooLargeFixedStep). Stop
      // instead, naming the bound, when the step exceeds a stability limit of the current state
      // (kViscousLimitFactor above).
      const StepInputs in = currentStepInputs(params_, particles_, bodies_.get(), *solver_);
      TimeStepParams limits = params_.timeStep;
      limits.cflFactor = limits.forceFactor = limits.springFactor = 1.0f;
      limits.pressureFactor = kPressureLimitFactor;
      limits.viscousFactor = kViscousLimitFactor;
      const StepLimit edge = stabilityBound(limits, in);
      if (params_.timeStep.fixedStep > edge.step) {
        std::ostringstream msg;
        msg << "time " << time_ << " s: the fixed step " << params_.timeStep.fixedStep << " s exceeds the "
            << stepBoundName(edge.bound) << " stability limit of the current state, " << edge.step << " s ("
            << params_.timeStep.fixedStep / edge.step << " times it; an explicit step beyond it is unstable); use "
            << "time_step.fixed_step <= " << stabilityBound(params_.timeStep, in).step
            << " s (the adaptive step now) or time_step.mode \"adaptive\"";
        throw SimulationError(msg.str());
      }
    }
    const double remaining = t - time_;
    float dt = limit.step;
    if (remaining <= dt) dt = float(remaining);                    // land exactly on the frame
    else if (remaining < 1.5 * dt) dt = float(0.5 * remaining);    // avoid a sliver step
    ++stats_.boundCounts[size_t(limit.bound)];
    addBodyForces(dt);
    integrate(dt, remaining <= limit.step ? t : time_ + dt);  // frames land on their exact time
    const float vmax = maxOver(particles_.size(), [&](size_t i) {
      const float s = std::fabs(particles_.vx[i]) + std::fabs(particles_.vy[i]) + std::fabs(particles_.vz[i]);
      return std::isfinite(s) ? s : std::numeric_limits<float>::infinity();
    });
    if (!std::isfinite(vmax)) {
      std::ostringstream msg;
      msg << "time " << time_ << " s: a particle velocity became non-finite (the step " << dt << " s, set by the "
          << stepBoundName(limit.bound) << " bound, is too large for the scene's stiffness; try a smaller time_step)";
      throw SimulationError(msg.str());
    }
    if (solveCutShort_ || (stopAfterStep_ && stopAfterStep_())) {
      std::ostringstream msg;
      msg << "stopped at t = " << time_ << " s, before t = " << t << " s"
          << (solveCutShort_ ? " (a solve cut short)" : "");
      const bool cut = solveCutShort_;
      solveCutShort_ = false;
      throw Stopped(msg.str(), cut);
    }
  }
}

namespace {
// Every per-particle array, in one fixed order.
template <class P, class F>
void forEachArray(P& p, F&& f) {
  for (auto* a : {&p.x, &p.y, &p.z, &p.vx, &p.vy, &p.vz, &p.ax, &p.ay, &p.az, &p.density, &p.pressure,
                                &p.restDensity, &p.mass})
    f(*a);
  f(p.id);
  f(p.kind);
}
constexpr uint64_t kStateMagic = 0x4b55524147455354ull;  // "KURAGEST"
}  // namespace

void Simulation::saveState(StateWriter& out) const {
  out.value(kStateMagic);
  out.value(uint64_t(particles_.size()));
  forEachArray(particles_, [&](const auto& a) { out.array(a); });
  out.value(time_);
  out.value(lastStep_);
  out.value(nextId_);
  out.value(stats_);
  solver_->saveState(out);
  out.value(uint64_t(emitters_.size()));
  for (const Emitter& e : emitters_) e.saveState(out);
  out.value(uint8_t(bodies_ != nullptr));
  if (bodies_) bodies_->saveState(out);
}

void Simulation::restoreState(StateReader& in) {
  if (in.value<uint64_t>() != kStateMagic) throw StateError("checkpoint state: not a simulation's state");
  const uint64_t n = in.value<uint64_t>();
  // At most the particles the scene can hold: those built plus every emitter's whole output.
  uint64_t most = particles_.size();
  for (const Emitter& e : emitters_) most += e.expectedTotal();
  if (n > most)
    throw StateError("checkpoint state: " + std::to_string(n) + " particles, more than the scene can make (" +
                     std::to_string(most) + ")");
  ParticleSet p;
  p.reserve(size_t(most));
  forEachArray(p, [&](auto& a) { in.arrayOf(a, n); });
  const double time = in.value<double>();
  const float lastStep = in.value<float>();
  const int64_t nextId = in.value<int64_t>();
  const SimStats stats = in.value<SimStats>();
  if (!std::isfinite(time) || time < 0.0 || !std::isfinite(lastStep) || nextId < 0)
    throw StateError("checkpoint state: time, step or ids out of range");
  // Body particles (ids below the bodies' count) must all be there, once each.
  const size_t bodyCount = bodies_ ? bodies_->particleCount() : 0;
  std::vector<uint8_t> seen(bodyCount, 0);
  for (size_t i = 0; i < n; ++i) {
    if (p.id[i] < 0 || p.id[i] >= nextId) throw StateError("checkpoint state: a particle id out of range");
    if (size_t(p.id[i]) < bodyCount) {
      if (seen[size_t(p.id[i])]++) throw StateError("checkpoint state: a body particle twice");
    } else if (p.kind[i] != 0) {
      throw StateError("checkpoint state: a fluid particle id with a body's kind");
    }
  }
  if (std::find(seen.begin(), seen.end(), uint8_t(0)) != seen.end())
    throw StateError("checkpoint state: body particles missing");
  solver_->restoreState(in);
  if (in.value<uint64_t>() != emitters_.size()) throw StateError("checkpoint state: the emitters do not fit the scene");
  for (Emitter& e : emitters_) e.restoreState(in);
  if (in.value<uint8_t>() != uint8_t(bodies_ != nullptr)) throw StateError("checkpoint state: the bodies do not fit the scene");
  if (bodies_) bodies_->restoreState(in);
  if (!in.done()) throw StateError("checkpoint state: bytes left over");
  particles_ = std::move(p);
  time_ = time;
  lastStep_ = lastStep;
  nextId_ = nextId;
  stats_ = stats;
}

}  // namespace kurage::sim
