#include "sim/solvers/dfsph/dfsph.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <stdexcept>
#include <utility>

namespace kurage::sim {

namespace {
constexpr int kMinDensityIterations = 2;     // Bender & Koschier 2017, Algorithm 3
constexpr float kSurfaceDensityRatio = 0.9f; // below: left out of the divergence solve
constexpr float kMirror = 2.0f;               // the wall's pressure counts with the particle's (header)
constexpr float kRelaxation = 0.5f;          // Jacobi relaxation of the constant-density solve
constexpr float kDivergenceWarmStart = 0.5f; // of the previous step's divergence pressure (Jacobi)
constexpr float kCgDivergenceWarmStart = 0.8f;  // the same for conjugate gradients (header)
}  // namespace

void DfsphParams::describe(ParamVisitor& v) {
  v.value("max_density_error", maxDensityError,
          {"%", "dfsph: the constant-density solve iterates until the mean compression is below this, in percent "
                "of the rest density", positive()});
  v.value("max_divergence_error", maxDivergenceError,
          {"%", "dfsph: the divergence solve iterates until the mean density change over one step is below this, "
                "in percent of the rest density", positive()});
  v.value("max_iterations", maxIterations,
          {"", "dfsph: iteration cap of the constant-density solve (a step that reaches it is counted in "
               "run.json and warned about)", atLeast(1)});
  v.value("max_divergence_iterations", maxDivergenceIterations,
          {"", "dfsph: iteration cap of the divergence solve", atLeast(1)});
  v.enumeration("divergence_solve", divergenceSolve,
                EnumTable<DivergenceSolve>{{"jacobi", DivergenceSolve::Jacobi}, {"cg", DivergenceSolve::ConjugateGradient}},
                {"", "dfsph: how the divergence solve iterates: 'jacobi' (relaxed Jacobi, as Bender & Koschier) or "
                     "'cg' (preconditioned conjugate gradients on the same equations: about half the iterations "
                     "for the same tolerance; docs/design/physics.md says what else changes)"});
}

std::optional<ParamProblem> DfsphParams::problem(const FluidParams& fluid) const {
  if (fluid.kernel == SphKernel::Mueller2003)
    return ParamProblem{"fluid.kernel", "dfsph's solves use the cubic spline: 'cubic_spline' or 'auto', got \"mueller2003\""};
  return std::nullopt;
}

DfsphSolver::DfsphSolver(const FluidParams& fluid)
    : params_(fluid.solver.as<DfsphParams>()), restDensity_(fluid.restDensity), kernel_(fluid.supportRadiusMetres()),
      form_(fluid.densitySum), maxDensityError_(0.01f * params_.maxDensityError),
      maxDivergenceError_(0.01f * params_.maxDivergenceError), maxIterations_(params_.maxIterations),
      maxDivergenceIterations_(params_.maxDivergenceIterations), divergenceSolve_(params_.divergenceSolve),
      sweeps_(solvers::sweepTable()), scalarSums_(sweeps_.isa == solvers::SweepIsa::Scalar || sweeps_.isa == solvers::SweepIsa::Lanes) {
  if (fluid.kernel == SphKernel::Mueller2003)
    throw std::invalid_argument("dfsph: its solves use the cubic spline kernel, not the paper's poly6 and spiky");
  latticeNeighbours_ = solvers::relaxedNeighbours(fluid.supportRadius);
}

using solvers::forEach;
using solvers::storeById;

template <class F>
double DfsphSolver::orderedSum(size_t count, F&& f) {
  return solvers::orderedSum(count, partial_, std::forward<F>(f));
}

StepNeeds DfsphSolver::needs() const {
  StepNeeds n;
  n.correctsVelocities = true;
  n.wallSums = true;
  n.gradientCorrection = true;
  return n;
}

std::string DfsphSolver::boundaryCouplingProblem(const FluidParams& fluid) const {
  if (fluid.densitySum != DensitySum::Volume)
    return "\"boundary\" needs fluid.density_sum \"volume\": the fluid counts a boundary sample by its volume "
           "m / rho0, which (10) grows as the body stretches";
  if (params_.divergenceSolve != DivergenceSolve::Jacobi)
    return "\"boundary\" needs fluid.divergence_solve \"jacobi\": spreading the reactions over spring patches "
           "makes the solves' operator unsymmetric, which conjugate gradients does not allow";
  return "";
}

void DfsphSolver::hydrostaticHead(const std::vector<float>& headById) {
  // The density solve's warm start pi = p / rho0^2 = g depth / rho0
  piById_.resize(headById.size());
  for (size_t id = 0; id < headById.size(); ++id) piById_[id] = headById[id] / restDensity_;
}

SolverCounters DfsphSolver::counters() const {
  return {stats_.steps,
          {{"density", stats_.density.iterations, stats_.density.capHits},
           {"divergence", stats_.divergence.iterations, stats_.divergence.capHits}}};
}

void DfsphSolver::report(SolverReport& out) const {
  stats_.density.report(out, "density_solve", stats_.steps, params_.maxIterations, 0.01 * params_.maxDensityError);
  out.add("divergence_solve.method", params_.divergenceSolve == DivergenceSolve::Jacobi ? "jacobi" : "cg");
  stats_.divergence.report(out, "divergence_solve", stats_.steps, params_.maxDivergenceIterations,
                           0.01 * params_.maxDivergenceError);
  stats_.torn.report(out);
  out.add("simd_path", sweeps_.name);  // the sweeps' floats are the path's (solvers/sweeps.h)
}

std::vector<SolverWarning> DfsphSolver::warnings() const {
  std::vector<SolverWarning> w;
  stats_.torn.warn(w, name(), stats_.steps);
  if (stats_.density.capHits || stats_.divergence.capHits)
    w.push_back({"the dfsph solver stopped at its iteration cap in " + std::to_string(stats_.density.capHits) +
                     " density and " + std::to_string(stats_.divergence.capHits) + " divergence solves of " +
                     std::to_string(stats_.steps) + " steps (fluid.max_iterations " +
                     std::to_string(params_.maxIterations) + ", fluid.max_divergence_iterations " +
                     std::to_string(params_.maxDivergenceIterations) +
                     "): the density error there is above the tolerance",
                 ""});
  return w;
}

void DfsphSolver::saveState(StateWriter& out) const {
  out.value(stats_);
  out.array(piById_);
  out.array(qById_);
}

void DfsphSolver::restoreState(StateReader& in) {
  stats_ = in.value<DfsphStats>();
  in.array(piById_, uint64_t(1) << 32);
  in.array(qById_, uint64_t(1) << 32);
}

void DfsphSolver::afterDensity(const SolverContext& c) {
  ParticleSet& p = c.particles;
  const size_t n = p.size();
  invFactor_.resize(n);
  active_.resize(n);
  fixed_.resize(n);
  relax_.resize(n);
  pi_.resize(n);
  change_.resize(n);
  rate_.resize(n);
  const size_t chunks = c.neighbors.chunkCount();
  const float dRef = 2.0f * kernel_.sigma * kernel_.invH;  // largest |dW/dr|, at r = h / 3
  position_.resize(n);
  velocity_.resize(n);
  response_.resize(n);
  const uint8_t* sample = c.boundaryBodies ? c.boundaryBodies->sample.data() : nullptr;
  tbb::parallel_for(size_t(0), n, [&](size_t i) {
    const float w = form_ == DensitySum::Mass ? p.mass[i] : p.mass[i] / p.restDensity[i];  // density rate weight
    // A boundary body's sample counts twice in its pairs with the fluid: the fluid particle's
    // pressure mirrored onto it (header, "Bodies as the fluid's boundary")
    position_[i] = Float4{p.x[i], p.y[i], p.z[i], sample && sample[i] ? kMirror * w : w};
    // Its weight c_i in a neighbour's D (header): a sample's undoubled, as if it answered the
    // neighbour's pressure alone (an approximation: it answers with its patch, mirrored; the
    // Jacobi iteration tolerates the factor's error)
    response_[i] = form_ == DensitySum::Mass ? w : w / p.restDensity[i];
  });
  loadVelocities(p);
  corrected_ = c.gradientCorrection != nullptr;
  if (corrected_ && n > 0) {
    origin_ = position_[n / 2];  // any particle's: applyPressure's sums stay near the differences they form
    origin_[3] = 0.0f;
  }
  if (corrected_) {
    correctionRows_.resize(3 * n);
    pushTerms_.resize(2 * n);
    pushZ_.resize(n);
    gradientSum_.resize(n);
    tbb::parallel_for(size_t(0), n, [&](size_t i) {
      const float* L = c.gradientCorrection + 6 * i;  // L00 L11 L22 L01 L02 L12 (fluid.h)
      correctionRows_[3 * i] = Float4{L[0], L[3], L[4], 0.0f};
      correctionRows_[3 * i + 1] = Float4{L[3], L[1], L[5], 0.0f};
      correctionRows_[3 * i + 2] = Float4{L[4], L[5], L[2], 0.0f};
    });
  }
  lanes_ = sweeps_.rateLanes != nullptr;
  if (lanes_) laneLists_.build(c.neighbors, n);
  // The walls' part of particle i's F (mirrored wall: see the header)
  const auto wallF = [&](size_t i) {
    Eigen::Vector3f gb = Eigen::Vector3f::Zero();
    if (c.boundaryGradient) gb = wallWeight(p, i) * Eigen::Vector3f(c.boundaryGradient + 3 * i);
    return Eigen::Vector3f(kMirror * gb);
  };
  // The factor of particle i from its sums F = sum_j w_j grad W_ij (+ the walls') and S = sum_j c_j |grad W_ij|^2
  const auto finish = [&](size_t i, const Eigen::Vector3f& F, float S) {
    const float rho0i = p.restDensity[i];
    const float D = F.squaredNorm() + p.mass[i] * S;  // (2017, eq. 13; header)
    const float ref = position_[i][3] * dRef;
    // A particle a pin holds and a torn one are no unknowns: the solves give them no pressure
    // and do not count their error (header).
    fixed_[i] = c.unsolved && c.unsolved[i] != kSolved;
    invFactor_[i] = D > 1e-6f * ref * ref && !fixed_[i] ? 1.0f / D : 0.0f;
    active_[i] = p.density[i] >= kSurfaceDensityRatio * rho0i && !fixed_[i];
    // Jacobi's largest eigenvalue grows with the neighbour count: a body at half the fluid
    // spacing has about 8 times the fluid's neighbours, and the iteration diverged there with
    // the fluid's relaxation (bodies under DFSPH went non-finite). Scaled down where a particle
    // has more neighbours than the fluid lattice, or than h = 2 l's lattice (constructor).
    const float count = float(c.neighbors.end(i) - c.neighbors.begin(i));
    relax_[i] = kRelaxation * std::min(1.0f, latticeNeighbours_ / std::max(count, 1.0f));
  };
  // With the corrected gradient: the walls' term keeps the plain gradient (L_i = I within h of a
  // wall; header); F's neighbour part is L_i sum_j w_j grad W_ij, from the plain sum, which the push
  // keeps (applyPressure).
  const auto correctedF = [&](size_t i, Float4 plain) {
    plain[3] = 0.0f;
    gradientSum_[i] = plain;
    const Float4 sum = corrected(i, plain);
    return Eigen::Vector3f(sum[0], sum[1], sum[2]);
  };
  if (lanes_) {  // eight particles at a time (sweeps.h, the lanes path)
    tbb::parallel_for(size_t(0), chunks, [&](size_t ch) {
      const solvers::LaneRow* rows = laneLists_.rows[ch].data();
      for (size_t gi = laneLists_.groupsBegin(ch); gi < laneLists_.groupsEnd(ch); ++gi) {
        const solvers::LaneGroup& g = laneLists_.groups[gi];
        Float4 F[solvers::LaneLists::kWidth] = {};
        float S[solvers::LaneLists::kWidth] = {};
        if (corrected_) {
          sweeps_.factorCorrectedLanes(rows, g, position_.data(), response_.data(), correctionRows_.data(), F, S);
          for (uint32_t l = 0; l < g.used; ++l) {
            const size_t i = g.self[l];
            finish(i, wallF(i) + correctedF(i, F[l]), S[l]);
          }
          continue;
        }
        for (uint32_t l = 0; l < g.used; ++l) {
          const Eigen::Vector3f w = wallF(g.self[l]);
          F[l] = Float4{w.x(), w.y(), w.z(), 0.0f};
        }
        sweeps_.factorLanes(rows, g, position_.data(), response_.data(), F, S);
        for (uint32_t l = 0; l < g.used; ++l) finish(g.self[l], Eigen::Vector3f(F[l][0], F[l][1], F[l][2]), S[l]);
      }
    });
  } else
  tbb::parallel_for(size_t(0), chunks, [&](size_t ch) {
    const std::vector<float>& g = c.neighbors.slopes(ch);  // W'(r)/r, from the density pass
    assert(g.size() == c.neighbors.chunkSize(ch));
    const size_t last = std::min(n, (ch + 1) * NeighborLists::kChunk);
    for (size_t i = ch * NeighborLists::kChunk; i < last; ++i) {
      Eigen::Vector3f F = wallF(i);
      float S = 0.0f;
      const float* slope = g.data() + c.neighbors.offset(i);
      if (!corrected_) {
        // sum_j w_j grad W_ij (w_j mirrored for a boundary body's sample) and sum_j c_j |grad W_ij|^2
        Float4 F4 = {F.x(), F.y(), F.z(), 0.0f};
        sweeps_.factor(c.neighbors.begin(i), c.neighbors.end(i), slope, position_.data(), response_.data(),
                       position_[i], F4, S);
        F = Eigen::Vector3f(F4[0], F4[1], F4[2]);
      } else {
        Float4 plain;
        solvers::correctedFactorSum(c.neighbors.begin(i), c.neighbors.end(i), slope, position_.data(),
                                    response_.data(), position_[i], correctionRows_.data() + 3 * i, plain, S);
        F += correctedF(i, plain);
      }
      finish(i, F, S);
    }
  });
  ++stats_.steps;
  stats_.torn.count(c.unsolved, n);
  qSum_.assign(n, 0.0f);
  // Divergence solve on the current velocities (before the first step there is no step size for
  // the tolerance, and the fluid starts at rest).
  if (maxDivergenceIterations_ <= 0 || !(c.lastStep > 0.0f) || n == 0) return;
  int iterations = 0;
  double error = 0.0;
  bool capped = false;
  // Warm start (header): a share of each fluid particle's q of the previous step, by id.
  const float share =
      divergenceSolve_ == DivergenceSolve::ConjugateGradient ? kCgDivergenceWarmStart : kDivergenceWarmStart;
  const bool warm = orderedSum(n, [&](size_t i) {
    const size_t id = size_t(p.id[i]);
    qSum_[i] = active_[i] && p.kind[i] == 0 && id < qById_.size() ? share * qById_[id] * unit(p, i) : 0.0f;
    return qSum_[i] != 0.0f ? 1.0 : 0.0;
  }) > 0.0;
  if (warm) applyPressure(c, qSum_.data(), 1.0f, velocity_.data());
  if (divergenceSolve_ == DivergenceSolve::ConjugateGradient) iterations = divergenceCg(c, error, capped);
  else for (;;) {
    densityRate(c, velocity_.data());
    const double sum = orderedSum(n, [&](size_t i) {
      // Inside the liquid (rho_i >= 0.9 rho0_i) the velocity field is made divergence-free both
      // ways: a region that separates is drawn together as one that converges is pushed apart
      // (q < 0 where it separates); with only the compressing part, as in SPlisHSPlasH, a still
      // tank kept a bouncing mode that the constant-density solve, which never pulls, let grow.
      const float d = !active_[i] ? 0.0f : p.kind[i] == 0 ? rate_[i] : std::max(rate_[i], 0.0f);
      change_[i] = relax_[i] * d * invFactor_[i];
      // The error counts |d|: counting the compressing part only, as SPlisHSPlasH does, halves the
      // iterations but took Martin & Moyce's column height from 10.5 to 13.1 % (docs/design/physics.md).
      return double(std::fabs(d)) / p.restDensity[i];
    });
    error = sum / double(n) * c.lastStep;
    if (error <= maxDivergenceError_) break;
    if (iterations >= maxDivergenceIterations_) { capped = true; break; }
    if (c.stopRequested()) break;
    applyPressure(c, change_.data(), 1.0f, velocity_.data());  // q = dt pi^v: the step cancels (2017, eq. 16)
    forEach(n, [&](size_t i) { qSum_[i] += change_[i]; });
    ++iterations;
  }
  storeVelocities(p);
  forEach(n, [&](size_t i) { qSum_[i] /= unit(p, i); });
  storeById(p, qSum_, qById_);
  stats_.divergence.record(iterations, error, capped);
}

int DfsphSolver::divergenceCg(const SolverContext& c, double& error, bool& capped) {
  ParticleSet& p = c.particles;
  const size_t n = p.size();
  residual_.resize(n);
  direction_.resize(n);
  weight_.resize(n);
  scratch_.resize(n);
  densityRate(c, velocity_.data());
  tbb::parallel_for(size_t(0), n, [&](size_t i) {
    // The unknowns of particles inside the liquid; a body particle only where it compresses.
    const bool in = active_[i] && (p.kind[i] == 0 || rate_[i] > 0.0f);
    residual_[i] = in ? rate_[i] : 0.0f;
    // <a, b> = sum_i c_i a_i b_i, in which the operator is self-adjoint (header)
    weight_[i] = in ? (form_ == DensitySum::Mass ? p.mass[i] : position_[i][3] / p.restDensity[i]) : 0.0f;
    change_[i] = residual_[i] * invFactor_[i];  // z = M^-1 r
    direction_[i] = change_[i];
  });
  const auto measure = [&] {
    return orderedSum(n, [&](size_t i) { return double(std::fabs(residual_[i])) / p.restDensity[i]; }) / double(n) *
           c.lastStep;
  };
  error = measure();
  double rz = orderedSum(n, [&](size_t i) { return double(weight_[i]) * residual_[i] * change_[i]; });
  int iterations = 0;
  while (error > maxDivergenceError_) {
    if (iterations >= maxDivergenceIterations_) { capped = true; break; }
    if (c.stopRequested()) break;
    // A d: the density rate of the velocities -P d (scratch_), negated, on the unknowns' set.
    tbb::parallel_for(size_t(0), n, [&](size_t i) { scratch_[i] = Float4{0.0f, 0.0f, 0.0f, 0.0f}; });
    applyPressure(c, direction_.data(), 1.0f, scratch_.data());
    densityRate(c, scratch_.data());
    const double dAd = orderedSum(n, [&](size_t i) { return -double(weight_[i]) * direction_[i] * rate_[i]; });
    if (!(dAd > 0.0) || !(rz > 0.0)) break;
    const float alpha = float(rz / dAd);
    tbb::parallel_for(size_t(0), n, [&](size_t i) {
      velocity_[i] += alpha * scratch_[i];
      qSum_[i] += alpha * direction_[i];
      if (weight_[i] != 0.0f) residual_[i] += alpha * rate_[i];  // r - alpha A d
    });
    ++iterations;
    error = measure();
    if (error <= maxDivergenceError_) break;
    const double rzNext = orderedSum(n, [&](size_t i) {
      change_[i] = residual_[i] * invFactor_[i];  // z = M^-1 r
      return double(weight_[i]) * residual_[i] * change_[i];
    });
    const float beta = float(rzNext / rz);
    rz = rzNext;
    tbb::parallel_for(size_t(0), n, [&](size_t i) { direction_[i] = change_[i] + beta * direction_[i]; });
  }
  return iterations;
}

void DfsphSolver::loadVelocities(const ParticleSet& p) {
  tbb::parallel_for(size_t(0), p.size(), [&](size_t i) { velocity_[i] = Float4{p.vx[i], p.vy[i], p.vz[i], 0.0f}; });
}

void DfsphSolver::storeVelocities(ParticleSet& p) const {
  tbb::parallel_for(size_t(0), p.size(), [&](size_t i) {
    p.vx[i] = velocity_[i][0]; p.vy[i] = velocity_[i][1]; p.vz[i] = velocity_[i][2];
  });
}

void DfsphSolver::densityRate(const SolverContext& c, const Float4* v) {
  const ParticleSet& p = c.particles;
  const size_t n = p.size();
  const Float4* x = position_.data();
  // The rate of particle i from its neighbour sum `rate` (sum_j w_j (v_i - v_j) . grad W_ij)
  const auto finish = [&](size_t i, float rate) {
    if (form_ == DensitySum::Volume) rate *= p.restDensity[i];
    if (c.boundaryGradient) {
      const float* gb = c.boundaryGradient + 3 * i;
      const Float4 vi = v[i];
      rate += kMirror * p.restDensity[i] * (vi[0] * gb[0] + vi[1] * gb[1] + vi[2] * gb[2]);  // mirrored wall at rest: see the header
    }
    rate_[i] = rate;  // (2017, eq. 9)
  };
  // sum_j w_j (v_i - v_j) . L_i grad W_ij = sum_a L_i,a . T_a, T_a = sum_j w_j (v_i - v_j)_a grad W_ij
  const auto correctedRate = [&](size_t i, const Float4* t) {
    const Float4 r = correctionRows_[3 * i] * t[0] + correctionRows_[3 * i + 1] * t[1] + correctionRows_[3 * i + 2] * t[2];  // rows . T_a
    return r[0] + r[1] + r[2];
  };
  if (lanes_) {  // eight particles at a time (sweeps.h, the lanes path)
    tbb::parallel_for(size_t(0), c.neighbors.chunkCount(), [&](size_t ch) {
      const solvers::LaneRow* rows = laneLists_.rows[ch].data();
      for (size_t gi = laneLists_.groupsBegin(ch); gi < laneLists_.groupsEnd(ch); ++gi) {
        const solvers::LaneGroup& g = laneLists_.groups[gi];
        if (corrected_) {
          Float4 t[3 * solvers::LaneLists::kWidth];
          sweeps_.rateCorrectedLanes(rows, g, x, v, t);
          for (uint32_t l = 0; l < g.used; ++l) finish(g.self[l], correctedRate(g.self[l], t + 3 * l));
          continue;
        }
        alignas(32) float sums[solvers::LaneLists::kWidth];
        sweeps_.rateLanes(rows, g, x, v, sums);
        for (uint32_t l = 0; l < g.used; ++l) finish(g.self[l], sums[l]);
      }
    });
    return;
  }
  tbb::parallel_for(size_t(0), c.neighbors.chunkCount(), [&](size_t ch) {
    const size_t last = std::min(n, (ch + 1) * NeighborLists::kChunk);
    const float* s0 = c.neighbors.slopes(ch).data();
    for (size_t i = ch * NeighborLists::kChunk; i < last; ++i) {
      const Float4 xi = x[i], vi = v[i];
      const float* s = s0 + c.neighbors.offset(i);
      // Summed per axis in one register, the three axes added once at the end (a horizontal sum
      // per pair cost about 10 % of a step).
      float rate;
      if (!corrected_) {
        if (scalarSums_) {  // inline: a call a particle cost the scalar path a few % of a step
          const Float4 sum = solvers::rateSum(c.neighbors.begin(i), c.neighbors.end(i), s, x, v, xi, vi);
          rate = sum[0] + sum[1] + sum[2];
        } else {
          rate = sweeps_.rate(c.neighbors.begin(i), c.neighbors.end(i), s, x, v, xi, vi);
        }
      } else {
        Float4 t[3];
        solvers::correctedRateSum(c.neighbors.begin(i), c.neighbors.end(i), s, x, v, xi, vi, t);
        rate = correctedRate(i, t);
      }
      finish(i, rate);
    }
  });
}

void DfsphSolver::applyPressure(const SolverContext& c, const float* k, float scale, Float4* v) {
  ParticleSet& p = c.particles;
  const size_t n = p.size();
  const Float4* x = position_.data();
  const BoundaryBodies* bodies = c.boundaryBodies;
  if (bodies) reaction_.resize(n);
  if (corrected_)
    forEach(n, [&](size_t j) {
      // w_j k_j L_j as (L00, L11, L22) and (L01, L02, L12), and w_j k_j L_j (x_j - origin)
      const float kw = k[j] * x[j][3];
      const Float4* r = correctionRows_.data() + 3 * j;
      const Float4 y = kw * corrected(j, x[j] - origin_);
      pushTerms_[2 * j] = kw * Float4{r[0][0], r[1][1], r[2][2], r[0][1]};
      pushTerms_[2 * j + 1] = Float4{kw * r[0][2], kw * r[1][2], y[0], y[1]};
      pushZ_[j] = y[2];
    });
  // v_i's change from particle i's neighbour sum a (sum_j w_j (k_i + k_j) grad W_ij, or its
  // corrected form)
  const auto finish = [&](size_t i, Float4 a) {
    const bool sampled = bodies && bodies->sample[i];
    if (sampled) a *= kMirror;  // a boundary body's sample: its fluid neighbours' pressures mirrored (header)
    if (c.boundaryGradient) {
      const float* gb = c.boundaryGradient + 3 * i;
      const float s = kMirror * wallWeight(p, i) * k[i];  // psi_b (k_i + k_b), k_b = k_i
      a += Float4{s * gb[0], s * gb[1], s * gb[2], 0.0f};
    }
    if (sampled) reaction_[i] = Float4{0.0f, 0.0f, 0.0f, 0.0f};
    if (c.unsolved && c.unsolved[i] == kHeld) return;  // its velocity is the pin's
    a[3] = 0.0f;  // the weights' lane
    if (form_ == DensitySum::Volume) a *= 1.0f / p.restDensity[i];
    if (sampled) { reaction_[i] = (bodies->share[i] * scale) * a; return; }  // spread below
    v[i] -= scale * a;  // (2017, eq. 7; header)
  };
  // The corrected push of particle i from its neighbour sums m0 = (M00, M11, M22, M01),
  // m1 = (M02, M12, Y0, Y1) and y2 = Y2 (below): M_i x_i - Y_i + k_i L_i sum_j w_j grad W_ij
  const auto correctedPush = [&](size_t i, Float4 m0, Float4 m1, float y2) {
    const Float4 xo = x[i] - origin_;
    Float4 a = Float4{m0[0] * xo[0] + m0[3] * xo[1] + m1[0] * xo[2] - m1[2], m0[3] * xo[0] + m0[1] * xo[1] + m1[1] * xo[2] - m1[3],
                      m1[0] * xo[0] + m1[1] * xo[1] + m0[2] * xo[2] - y2, 0.0f};
    a += k[i] * corrected(i, gradientSum_[i]);
    return a;
  };
  if (lanes_) {  // eight particles at a time (sweeps.h, the lanes path)
    tbb::parallel_for(size_t(0), c.neighbors.chunkCount(), [&](size_t ch) {
      const solvers::LaneRow* rows = laneLists_.rows[ch].data();
      for (size_t gi = laneLists_.groupsBegin(ch); gi < laneLists_.groupsEnd(ch); ++gi) {
        const solvers::LaneGroup& g = laneLists_.groups[gi];
        if (corrected_) {
          Float4 m[2 * solvers::LaneLists::kWidth];
          alignas(32) float y2[solvers::LaneLists::kWidth];
          sweeps_.pushCorrectedLanes(rows, g, pushTerms_.data(), pushZ_.data(), m, y2);
          for (uint32_t l = 0; l < g.used; ++l) finish(g.self[l], correctedPush(g.self[l], m[2 * l], m[2 * l + 1], y2[l]));
          continue;
        }
        Float4 sums[solvers::LaneLists::kWidth];
        sweeps_.pushLanes(rows, g, x, k, sums);
        for (uint32_t l = 0; l < g.used; ++l) finish(g.self[l], sums[l]);
      }
    });
  } else
  tbb::parallel_for(size_t(0), c.neighbors.chunkCount(), [&](size_t ch) {
    const size_t last = std::min(n, (ch + 1) * NeighborLists::kChunk);
    const float* s0 = c.neighbors.slopes(ch).data();
    for (size_t i = ch * NeighborLists::kChunk; i < last; ++i) {
      const float ki = k[i];
      const Float4 xi = x[i];
      const float* sp = s0 + c.neighbors.offset(i);
      Float4 a = {0.0f, 0.0f, 0.0f, 0.0f};
      if (!corrected_) {
        // w_j (k_i + k_j) grad W_ij
        a = scalarSums_ ? solvers::pushSum(c.neighbors.begin(i), c.neighbors.end(i), sp, x, k, xi, ki)
                        : sweeps_.push(c.neighbors.begin(i), c.neighbors.end(i), sp, x, k, xi, ki);
      } else {
        // w_j (k_i L_i + k_j L_j) grad W_ij: the transpose of the corrected density rate (header).
        // The neighbours' part, sum_j s_ij w_j k_j L_j (x_i - x_j) = M_i x_i - Y_i with
        // M_i = sum_j s_ij (w_j k_j L_j) and Y_i = sum_j s_ij (w_j k_j L_j x_j): three packed
        // multiply-adds a neighbour on pushTerms_ (positions from the solver's origin); the own
        // part k_i L_i sum_j w_j grad W_ij from the step's gradient sums.
        Float4 m0, m1;
        float y2;
        solvers::correctedPushSum(c.neighbors.begin(i), c.neighbors.end(i), sp, pushTerms_.data(), pushZ_.data(), m0,
                                  m1, y2);
        a = correctedPush(i, m0, m1, y2);
      }
      finish(i, a);
    }
  });
  if (!bodies) return;
  // Each sample's reaction spread over its patch (header): particle q of a patch gains
  // m_i dv_i / M_i, M_i the patch's mass, from every patch i it lies in (the patches are
  // symmetric: q lies in i's exactly when i lies in q's), gathered in the patch's order.
  const uint32_t* patch = bodies->patch.data();
  forEach(n, [&](size_t q) {
    if (!bodies->sample[q] || (c.unsolved && c.unsolved[q] == kHeld)) return;  // a pin takes its share
    Float4 d = {0.0f, 0.0f, 0.0f, 0.0f};
    for (uint32_t e = bodies->offsets[q]; e < bodies->offsets[q + 1]; ++e) d += reaction_[patch[e]];
    v[q] -= d;
  });
}

void DfsphSolver::correctVelocities(const SolverContext& c, float dt) {
  ParticleSet& p = c.particles;
  const size_t n = p.size();
  if (n == 0) return;
  const bool warm = orderedSum(n, [&](size_t i) {
    const size_t id = size_t(p.id[i]);
    pi_[i] = id < piById_.size() && !fixed_[i] ? piById_[id] * unit(p, i) : 0.0f;
    return pi_[i] != 0.0f ? 1.0 : 0.0;
  }) > 0.0;
  loadVelocities(p);  // v*
  if (warm) applyPressure(c, pi_.data(), dt, velocity_.data());
  if (c.boundaryLift)
    forEach(n, [&](size_t i) {
      // The walls' hydrostatic part of their pressure, p_b - p_i = rho0_i g . (x_b - x_i) (Adami
      // 2012): -dt sum_b psi_b (p_b - p_i) / rho0_i^2 grad W_ib, known before the solve.
      if (c.unsolved && c.unsolved[i] == kHeld) return;  // its velocity is the pin's
      if (c.boundaryBodies && c.boundaryBodies->sample[i]) return;  // no pressure of its own to mirror (header)
      const float* lift = c.boundaryLift + 3 * i;
      velocity_[i] -= dt * Float4{lift[0], lift[1], lift[2], 0.0f};
    });
  if (c.boundaryGradient) wetWalls(c, dt);
  const float invDt2 = 1.0f / (dt * dt);
  int iterations = 0;
  double error = 0.0;
  bool capped = false;
  for (;;) {
    densityRate(c, velocity_.data());
    const double sum = orderedSum(n, [&](size_t i) {
      if (fixed_[i]) { change_[i] = 0.0f; return 0.0; }  // no unknown (afterDensity)
      const float e = p.density[i] + dt * rate_[i] - p.restDensity[i];  // rho*_i - rho0_i
      const float next = std::max(0.0f, pi_[i] + relax_[i] * e * invDt2 * invFactor_[i]);
      change_[i] = next - pi_[i];
      // The residual of the complementarity problem (pressure >= 0, rho* = rho0 where it is
      // positive, rho* <= rho0 where it is 0): |e| where the particle keeps a pressure, the
      // compression alone where it has none (header)
      return double(next > 0.0f ? std::fabs(e) : std::max(e, 0.0f)) / p.restDensity[i];
    });
    error = sum / double(n);
    if (iterations >= kMinDensityIterations && error <= maxDensityError_) break;
    if (iterations >= maxIterations_) { capped = true; break; }
    if (c.stopRequested()) break;
    applyPressure(c, change_.data(), dt, velocity_.data());
    forEach(n, [&](size_t i) { pi_[i] += change_[i]; });
    ++iterations;
  }
  storeVelocities(p);
  // q was solved at this step's start with the step before it (c.lastStep, still that until the
  // positions move)
  const float invQStep = c.lastStep > 0.0f ? 1.0f / c.lastStep : 0.0f;
  forEach(n, [&](size_t i) {
    pi_[i] /= unit(p, i);
    // The pressure both solves applied this step: pi dt from the density solve, q from the
    // divergence one (header)
    p.pressure[i] = (pi_[i] + qSum_[i] * invQStep) * p.density[i] * p.density[i];
  });
  storeById(p, pi_, piById_);
  stats_.density.record(iterations, error, capped);
}

void DfsphSolver::wetWalls(const SolverContext& c, float dt) {
  const ParticleSet& p = c.particles;
  const size_t n = p.size();
  const float rho0 = c.fluid.restDensity;
  // Per body: the mean of p_j - rho0 g . x_j over its particles' fluid neighbours (last step's
  // pressures), so that the film's pressure at x is that mean + rho0 g . x.
  int bodies = 0;
  bool touching = false;  // some body particle within a wall's reach
  for (size_t i = 0; i < n; ++i) {
    if (p.kind[i] == 0) continue;
    bodies = std::max(bodies, int(p.kind[i]));
    const float* gb = c.boundaryGradient + 3 * i;
    touching = touching || gb[0] != 0.0f || gb[1] != 0.0f || gb[2] != 0.0f;
  }
  if (!touching) return;
  headSum_.assign(size_t(bodies) + 1, 0.0);
  headCount_.assign(size_t(bodies) + 1, 0.0);
  for (size_t i = 0; i < n; ++i) {
    if (p.kind[i] == 0) continue;
    for (const uint32_t* it = c.neighbors.begin(i); it != c.neighbors.end(i); ++it)
      if (p.kind[*it] == 0) {
        const uint32_t j = *it;
        headSum_[size_t(p.kind[i])] += double(p.pressure[j]) -
                                       double(rho0) * (c.gravity.x() * p.x[j] + c.gravity.y() * p.y[j] + c.gravity.z() * p.z[j]);
        headCount_[size_t(p.kind[i])] += 1.0;
      }
  }
  for (size_t i = 0; i < n; ++i) {
    const size_t k = size_t(p.kind[i]);
    if (k == 0 || headCount_[k] == 0.0 || (c.unsolved && c.unsolved[i] == kHeld)) continue;
    if (c.boundaryBodies && c.boundaryBodies->sample[i]) continue;  // a boundary body's: the fluid's own push (header)
    const float* gb = c.boundaryGradient + 3 * i;
    if (gb[0] == 0.0f && gb[1] == 0.0f && gb[2] == 0.0f) continue;
    const float film = float(headSum_[k] / headCount_[k]) +
                       rho0 * (c.gravity.x() * p.x[i] + c.gravity.y() * p.y[i] + c.gravity.z() * p.z[i]);
    const float extra = std::max(0.0f, film - p.pressure[i]);  // the wall's p_b = max(p_i, film)
    const float s = dt * extra / p.restDensity[i];
    velocity_[i] -= Float4{s * gb[0], s * gb[1], s * gb[2], 0.0f};
  }
}

size_t DfsphSolver::memoryBytes() const {
  size_t b = (position_.capacity() + velocity_.capacity()) * sizeof(Float4) + (invFactor_.capacity() + response_.capacity() + relax_.capacity() + pi_.capacity() + change_.capacity() + rate_.capacity() + piById_.capacity() + qSum_.capacity() + qById_.capacity() + residual_.capacity() + direction_.capacity() + weight_.capacity()) *
             sizeof(float) + active_.capacity() + fixed_.capacity();
  b += laneLists_.memoryBytes();
  b += (scratch_.capacity() + reaction_.capacity() + correctionRows_.capacity() + gradientSum_.capacity() + pushTerms_.capacity()) * sizeof(Float4) + pushZ_.capacity() * sizeof(float);
  return b;
}

}  // namespace kurage::sim
