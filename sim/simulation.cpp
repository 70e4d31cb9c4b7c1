#include "sim/simulation.h"

#include "sim/boundary.h"
#include "sim/fluid.h"
#include "sim/setup.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>

namespace kurage::sim {

std::string_view stageName(Stage stage) {
  switch (stage) {
    case Stage::Sort: return "neighbour_sort";
    case Stage::Density: return "density";
    case Stage::TelescopicDensity: return "telescopic_density";
    case Stage::Pressure: return "pressure";
    case Stage::Forces: return "pressure_viscosity_forces";
    case Stage::Springs: return "springs";
    case Stage::Muscles: return "muscles";
    case Stage::Integrate: return "integrate";
    case Stage::Pins: return "pins";
    case Stage::Collisions: return "collisions";
    case Stage::Walls: return "walls";
    case Stage::Emitters: return "emitters";
    case Stage::Sinks: return "sinks";
    case Stage::Count: break;
  }
  return "?";
}

namespace {
class StageTimer {
public:
  StageTimer(SimStats& stats, Stage stage) : stats_(stats), stage_(stage), start_(std::chrono::steady_clock::now()) {}
  ~StageTimer() {
    ++stats_.stageCalls[size_t(stage_)];
    stats_.stageSeconds[size_t(stage_)] +=
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  }
private:
  SimStats& stats_;
  Stage stage_;
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
      viscosity_(params_.fluid.supportRadiusMetres()) {
  const FluidParams& fluid = params_.fluid;
  if (!(fluid.spacing > 0.0f) || !(fluid.supportRadius > 0.0f) || !(fluid.restDensity > 0.0f))
    throw std::invalid_argument("simulation: spacing, support radius and rest density must be > 0");
  grid_.configure(params_.container.min, params_.container.max, fluid.supportRadiusMetres());
  fluidMass_ = calibratedParticleMass(fluid.spacing, fluid.supportRadiusMetres(), fluid.restDensity);
  if (params_.container.wallDensity == WallDensity::WallWeight) {
    wallWeights_ = std::make_unique<WallWeights>(fluid.spacing, fluid.supportRadiusMetres(), fluidMass_);
    wallSums_.weights = wallWeights_.get();
  }
  wallSums_.box = params_.container;
  wallSums_.restDensity = fluid.restDensity;
  std::vector<std::vector<Eigen::Vector3f>> blockPoints;
  size_t expected = 0;
  for (const FluidBlock& block : params_.fluidBlocks) {
    blockPoints.push_back(latticePoints(block, fluid.spacing));
    expected += blockPoints.back().size();
  }
  for (const EmitterParams& e : params_.emitters) {
    emitters_.emplace_back(e, fluid.spacing);
    expected += emitters_.back().expectedTotal();
  }
  if (!params_.bodies.empty()) {
    bodies_ = std::make_unique<BodySystem>(params_, particles_, nextId_);  // body ids first
    removeDisplacedFluid(particles_, fluid.spacing, params_.bodies, blockPoints);
  }
  particles_.reserve(particles_.size() + expected);
  for (const std::vector<Eigen::Vector3f>& points : blockPoints)
    for (const Eigen::Vector3f& q : points)
      particles_.add(q.x(), q.y(), q.z(), 0, 0, 0, fluid.restDensity, fluidMass_, nextId_++, 0);
}

void Simulation::sortParticles() {
  StageTimer timer(stats_, Stage::Sort);
  grid_.sort(particles_.x.data(), particles_.y.data(), particles_.z.data(), particles_.size(), order_);
  particles_.permute(order_, scratch_);
}

void Simulation::computeAccelerations() {
  sortParticles();
  if (bodies_) bodies_->index(particles_);
  // (4)-(5) depend only on positions, so they run before (3): the volume-weighted density sum
  // needs the neighbours' rest densities of this step.
  if (bodies_ && bodies_->hasTelescopicDensity()) {
    StageTimer timer(stats_, Stage::TelescopicDensity);
    bodies_->updateRestDensity(particles_);
  }
  {
    StageTimer timer(stats_, Stage::Density);
    computeDensity(grid_, particles_, poly6_, neighbors_, wallSums_, params_.fluid.densitySum);
  }
  {
    StageTimer timer(stats_, Stage::Pressure);
    computePressure(particles_, params_.fluid.pressureStiffness, params_.fluid.negativePressure);
  }
  {
    StageTimer timer(stats_, Stage::Forces);
    const float mu = params_.fluid.restDensity * params_.fluid.kinematicViscosity;  // mu = rho0 nu
    const bool correct = params_.fluid.gradientCorrection && params_.fluid.pressureForce == PressureForce::Monaghan1992;
    if (correct) computeGradientCorrection(neighbors_, particles_, spiky_, params_.container, correction_);
    computeFluidAcceleration(neighbors_, particles_, spiky_, viscosity_, mu, params_.gravity,
                             params_.fluid.pressureForce, wallSums_, correct ? correction_.data() : nullptr);
  }
}

void Simulation::addBodyForces(float dt) {
  if (!bodies_) return;
  if (bodies_->hasMuscles()) {
    StageTimer timer(stats_, Stage::Muscles);
    bodies_->addMuscleForces(particles_, time_);
  }
  {
    StageTimer timer(stats_, Stage::Springs);
    bodies_->addSpringForces(particles_, dt);  // (9), last: an implicit damper needs every other force
  }
}

void Simulation::integrate(float dt, double newTime) {
  {
    StageTimer timer(stats_, Stage::Integrate);
    ParticleSet& p = particles_;
    tbb::parallel_for(tbb::blocked_range<size_t>(0, p.size(), 4096), [&](const tbb::blocked_range<size_t>& r) {
      for (size_t i = r.begin(); i != r.end(); ++i) {
        // (12) v* = v + a dt, (13) x* = x + v* dt: symplectic Euler
        p.vx[i] += p.ax[i] * dt; p.vy[i] += p.ay[i] * dt; p.vz[i] += p.az[i] * dt;
        p.x[i] += p.vx[i] * dt; p.y[i] += p.vy[i] * dt; p.z[i] += p.vz[i] * dt;
      }
    });
  }
  if (bodies_ && bodies_->hasPins()) {
    StageTimer timer(stats_, Stage::Pins);
    bodies_->applyPins(particles_, newTime);
  }
  if (bodies_) {
    StageTimer timer(stats_, Stage::Collisions);
    bodies_->collide(particles_, params_.collisions.maxPasses, newTime);  // (14)
  }
  {
    StageTimer timer(stats_, Stage::Walls);
    enforceBoxWalls(particles_, params_.container, wallSums_.weights ? 0.5f * params_.fluid.spacing : 0.0f);  // (15)
  }
  time_ = newTime;
  if (!emitters_.empty()) {
    StageTimer timer(stats_, Stage::Emitters);
    for (Emitter& e : emitters_) {
      const uint64_t blockedBefore = e.blocked();
      stats_.emitted += e.emit(time_, dt, particles_, fluidMass_, params_.fluid.restDensity, nextId_);
      stats_.emitterBlocked += e.blocked() - blockedBefore;
    }
  }
  if (!params_.sinks.empty()) {
    StageTimer timer(stats_, Stage::Sinks);
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
StepInputs currentStepInputs(const SimParams& params, const ParticleSet& p, const BodySystem* bodies) {
  StepInputs in;
  in.supportRadius = params.fluid.supportRadiusMetres();
  in.speedOfSound = params.fluid.speedOfSound();
  in.kinematicViscosity = params.fluid.kinematicViscosity;
  in.maxSpeed = std::sqrt(maxOver(p.size(), [&](size_t i) {
    return p.vx[i] * p.vx[i] + p.vy[i] * p.vy[i] + p.vz[i] * p.vz[i];
  }));
  in.maxAcceleration = std::sqrt(maxOver(p.size(), [&](size_t i) {
    return p.ax[i] * p.ax[i] + p.ay[i] * p.ay[i] + p.az[i] * p.az[i];
  }));
  if (bodies) in.springStep = bodies->springStep();
  return in;
}

// A fixed step above the stability limits of the current state stops the run. The limits are the
// adaptive bounds without their safety factors (time_step.*_factor: cfl 0.4, force 0.25, spring
// 0.5): a Courant number of 1, h / (c + |v|max); the explicit spring and damper limit
// min sqrt(2 m / K), m / D (a Gershgorin bound: exact for a chain, up to about 2 times too strict
// for a 3-D body with an implicit damper); sqrt(h / |a|max). The viscous bound keeps its default
// factor: 1.5 times 0.125 h^2 / nu already gains energy. Measured in docs/STABILITY.md.
constexpr float kViscousLimitFactor = 0.125f;
}  // namespace

StepLimit Simulation::nextStepLimit() const {
  const TimeStepParams& ts = params_.timeStep;
  if (ts.mode == TimeStepMode::Fixed) return {ts.fixedStep, StepBound::Fixed};
  return adaptiveStep(ts, currentStepInputs(params_, particles_, bodies_.get()));
}

StepLimit Simulation::stabilityLimit() const {
  StepInputs in;
  in.supportRadius = params_.fluid.supportRadiusMetres();
  in.speedOfSound = params_.fluid.speedOfSound();
  in.kinematicViscosity = params_.fluid.kinematicViscosity;
  in.maxAcceleration = params_.gravity.norm();
  if (bodies_) in.springStep = bodies_->springStep();
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
         order_.capacity() * sizeof(uint32_t) + (bodies_ ? bodies_->memoryBytes() : 0);
}

void Simulation::advanceTo(double t) {
  while (time_ < t) {
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
      const StepInputs in = currentStepInputs(params_, particles_, bodies_.get());
      TimeStepParams limits = params_.timeStep;
      limits.cflFactor = limits.forceFactor = limits.springFactor = 1.0f;
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
  }
}

}  // namespace kurage::sim
