#include "sim/solvers/iisph/iisph.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace kurage::sim {

namespace {
constexpr int kMinIterations = 2;  // the paper's Algorithm 1
constexpr float kMirror = 2.0f;    // the wall's pressure counts with the particle's (header)
}  // namespace

void IisphParams::describe(ParamVisitor& v) {
  v.value("max_density_error", maxDensityError,
          {"%", "iisph: the same for its pressure solve (the mean error of the predicted densities)", positive()});
  v.value("max_iterations", maxIterations,
          {"", "iisph: the same for its pressure solve", atLeast(1)});
  v.value("relaxation", relaxation,
          {"", "iisph: the relaxed Jacobi iteration's omega (the paper's 0.5), scaled down for particles with more "
               "neighbours than the fluid's lattice", {0.0, 1.0, true, false}});
  v.value("warm_start", warmStart,
          {"", "iisph: the pressure solve starts from this fraction of each particle's pressure of the previous step "
               "(the paper's 0.5)", between(0.0, 1.0)});
}

std::optional<ParamProblem> IisphParams::problem(const FluidParams& fluid) const {
  if (fluid.kernel == SphKernel::Mueller2003)
    return ParamProblem{"fluid.kernel", "iisph's solve uses the cubic spline: 'cubic_spline' or 'auto', got \"mueller2003\""};
  if (fluid.gradientCorrection)
    return ParamProblem{"fluid.gradient_correction", "iisph has no corrected kernel gradient (wcsph and dfsph have)"};
  return std::nullopt;
}

IisphSolver::IisphSolver(const FluidParams& fluid)
    : params_(fluid.solver.as<IisphParams>()), restDensity_(fluid.restDensity), form_(fluid.densitySum),
      kernel_(fluid.supportRadiusMetres()), neighbourBound_(solvers::relaxedNeighbours(fluid.supportRadius)),
      sweeps_(solvers::sweepTable()) {
  if (const std::optional<ParamProblem> problem = params_.problem(fluid))
    throw std::invalid_argument(problem->key + ": " + problem->message);
}

StepNeeds IisphSolver::needs() const {
  StepNeeds n;
  n.correctsVelocities = true;
  n.wallSums = true;
  return n;
}

void IisphSolver::hydrostaticHead(const std::vector<float>& headById) {
  warmById_.resize(headById.size());
  for (size_t id = 0; id < headById.size(); ++id) warmById_[id] = headById[id] / restDensity_;  // p / rho0^2
}

void IisphSolver::afterDensity(const SolverContext& c) {
  ParticleSet& p = c.particles;
  const size_t n = p.size();
  position_.resize(n);
  invFactor_.resize(n);
  relax_.resize(n);
  held_.resize(n);
  std::vector<float>& response = rate_;  // scratch until the solve: w_j / s_j
  response.resize(n);
  const float dRef = 2.0f * kernel_.sigma * kernel_.invH;  // largest |dW/dr|, at r = h / 3
  tbb::parallel_for(size_t(0), n, [&](size_t i) {
    const float w = form_ == DensitySum::Mass ? p.mass[i] : p.mass[i] / p.restDensity[i];
    position_[i] = Float4{p.x[i], p.y[i], p.z[i], w};
    response[i] = form_ == DensitySum::Mass ? w : w / p.restDensity[i];
  });
  solvers::forEachWithSlopes(c.neighbors, n, [&](size_t i, const float* slope) {  // W'(r)/r, from the density pass
    const Float4 xi = position_[i];
    Float4 F = {0.0f, 0.0f, 0.0f, 0.0f};
    float S = 0.0f;
    for (const uint32_t* it = c.neighbors.begin(i); it != c.neighbors.end(i); ++it, ++slope) {
      const Float4 grad = *slope * (xi - position_[*it]);  // (its fourth lane unused)
      F += position_[*it][3] * grad;
      const Float4 g2 = grad * grad;
      S += response[*it] * (g2[0] + g2[1] + g2[2]);
    }
    if (c.boundaryGradient) {
      const float* gb = c.boundaryGradient + 3 * i;
      const float cw = kMirror * wallWeight(p, i);
      F += Float4{cw * gb[0], cw * gb[1], cw * gb[2], 0.0f};
    }
    const float D = F[0] * F[0] + F[1] * F[1] + F[2] * F[2] + p.mass[i] * S;  // (I4)
    const bool unknown = !c.unsolved || c.unsolved[i] == kSolved;
    held_[i] = c.unsolved && c.unsolved[i] == kHeld;
    const float ref = xi[3] * dRef;  // a neighbour at the kernel's steepest: D below a millionth of its is none
    invFactor_[i] = unknown && D > 1e-6f * ref * ref ? 1.0f / D : 0.0f;
    const float count = float(c.neighbors.end(i) - c.neighbors.begin(i));
    relax_[i] = params_.relaxation * std::min(1.0f, neighbourBound_ / std::max(count, 1.0f));
  });
  ++stats_.steps;
  stats_.torn.count(c.unsolved, n);
}

void IisphSolver::densityRate(const SolverContext& c, const Float4* v) {
  const ParticleSet& p = c.particles;
  solvers::forEachWithSlopes(c.neighbors, p.size(), [&](size_t i, const float* slope) {
    float rate = sweeps_.rate(c.neighbors.begin(i), c.neighbors.end(i), slope, position_.data(), v, position_[i], v[i]);
    if (form_ == DensitySum::Volume) rate *= p.restDensity[i];
    if (c.boundaryGradient) {
      const float* gb = c.boundaryGradient + 3 * i;
      rate += kMirror * p.restDensity[i] * (v[i][0] * gb[0] + v[i][1] * gb[1] + v[i][2] * gb[2]);  // walls at rest
    }
    rate_[i] = rate;  // (I2)
  });
}

void IisphSolver::accelerate(const SolverContext& c, const float* k) {
  const ParticleSet& p = c.particles;
  solvers::forEachWithSlopes(c.neighbors, p.size(), [&](size_t i, const float* slope) {
    if (held_[i]) {
      acceleration_[i] = Float4{0.0f, 0.0f, 0.0f, 0.0f};
      return;
    }
    Float4 a = sweeps_.push(c.neighbors.begin(i), c.neighbors.end(i), slope, position_.data(), k, position_[i], k[i]);
    if (c.boundaryGradient) {
      const float* gb = c.boundaryGradient + 3 * i;
      const float s = kMirror * wallWeight(p, i) * k[i];
      a += Float4{s * gb[0], s * gb[1], s * gb[2], 0.0f};
    }
    a[3] = 0.0f;
    if (form_ == DensitySum::Volume) a *= 1.0f / p.restDensity[i];
    acceleration_[i] = -a;  // (I1)
  });
}

void IisphSolver::correctVelocities(const SolverContext& c, float dt) {
  ParticleSet& p = c.particles;
  const size_t n = p.size();
  if (n == 0) return;
  velocity_.resize(n);
  acceleration_.resize(n);
  source_.resize(n);
  rate_.resize(n);
  k_.resize(n);
  next_.resize(n);
  solvers::forEach(n, [&](size_t i) {
    Float4 v = {p.vx[i], p.vy[i], p.vz[i], 0.0f};
    if (c.boundaryLift && !held_[i]) {
      // The walls' hydrostatic part of their pressure (Adami 2012; header), known before the solve
      const float* lift = c.boundaryLift + 3 * i;
      v -= dt * Float4{lift[0], lift[1], lift[2], 0.0f};
    }
    velocity_[i] = v;
    const size_t id = size_t(p.id[i]);
    k_[i] = invFactor_[i] != 0.0f && id < warmById_.size() ? warmById_[id] * unit(p, i) : 0.0f;
  });
  densityRate(c, velocity_.data());
  solvers::forEach(n, [&](size_t i) { source_[i] = p.density[i] + dt * rate_[i] - p.restDensity[i]; });
  const float dt2 = dt * dt, invDt2 = 1.0f / dt2;
  int iterations = 0;
  double error = 0.0;
  bool capped = false;
  for (;;) {
    accelerate(c, k_.data());
    densityRate(c, acceleration_.data());
    const double sum = solvers::orderedSum(n, partial_, [&](size_t i) {
      const float e = source_[i] + dt2 * rate_[i];  // rho*_i - rho0_i (I3)
      const float next = invFactor_[i] != 0.0f ? std::max(0.0f, k_[i] + relax_[i] * e * invDt2 * invFactor_[i]) : 0.0f;
      next_[i] = next;  // (I5)
      if (invFactor_[i] == 0.0f) return 0.0;
      return double(next > 0.0f ? std::fabs(e) : std::max(e, 0.0f)) / p.restDensity[i];
    });
    error = sum / double(n);
    if (iterations >= kMinIterations && error <= 0.01 * double(params_.maxDensityError)) break;
    if (iterations >= params_.maxIterations) { capped = true; break; }
    if (c.stopRequested()) break;
    std::swap(k_, next_);
    ++iterations;
  }
  const float warm = params_.warmStart;
  solvers::forEach(n, [&](size_t i) {
    if (!held_[i]) {
      p.vx[i] = velocity_[i][0] + dt * acceleration_[i][0];
      p.vy[i] = velocity_[i][1] + dt * acceleration_[i][1];
      p.vz[i] = velocity_[i][2] + dt * acceleration_[i][2];
    }
    const float pi = k_[i] / unit(p, i);  // p / rho^2
    p.pressure[i] = pi * p.density[i] * p.density[i];
    next_[i] = warm * pi;
  });
  solvers::storeById(p, next_, warmById_);
  stats_.density.record(iterations, error, capped);
}

SolverCounters IisphSolver::counters() const { return {stats_.steps, {{"density", stats_.density.iterations, stats_.density.capHits}}}; }

void IisphSolver::report(SolverReport& out) const {
  stats_.density.report(out, "density_solve", stats_.steps, params_.maxIterations, 0.01 * params_.maxDensityError);
  out.add("density_solve.relaxation", double(params_.relaxation));
  out.add("density_solve.warm_start", double(params_.warmStart));
  stats_.torn.report(out);
  out.add("simd_path", sweeps_.name);  // the sweeps' floats are the path's (solvers/sweeps.h)
}

std::vector<SolverWarning> IisphSolver::warnings() const {
  std::vector<SolverWarning> w;
  stats_.torn.warn(w, name(), stats_.steps);
  if (stats_.density.capHits)
    w.push_back({"the iisph solver stopped at its iteration cap in " + std::to_string(stats_.density.capHits) + " of " +
                     std::to_string(stats_.steps) + " steps (fluid.max_iterations " +
                     std::to_string(params_.maxIterations) + "): the density error there is above the tolerance",
                 ""});
  return w;
}

size_t IisphSolver::memoryBytes() const {
  return (position_.capacity() + velocity_.capacity() + acceleration_.capacity()) * sizeof(Float4) +
         (invFactor_.capacity() + relax_.capacity() + source_.capacity() + rate_.capacity() + k_.capacity() +
          next_.capacity() + warmById_.capacity()) * sizeof(float) + held_.capacity();
}

void IisphSolver::saveState(StateWriter& out) const {
  out.value(stats_);
  out.array(warmById_);
}

void IisphSolver::restoreState(StateReader& in) {
  stats_ = in.value<IisphStats>();
  in.array(warmById_, uint64_t(1) << 32);
}

}  // namespace kurage::sim
