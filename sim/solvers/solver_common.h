// Pieces the iterative pressure solvers share (dfsph/, iisph/): particle data packed four floats
// to a SIMD register, the neighbour sums of a density rate and of a pressure push over it, sums
// reduced in a fixed order, warm starts kept by particle id, the bound on a relaxed Jacobi
// iteration's neighbour count, and the count of torn body particles left out of the unknowns.
//
// Packing: a particle's position as (x, y, z, w), w its weight in the neighbours' sums (m_j, or
// m_j / rho0_j for density_sum "volume"), its velocity as (vx, vy, vz, 0), so that a neighbour's
// data is one load and a pair's arithmetic one instruction per operation (GCC and Clang vector
// extension). The kernel gradient is grad W_ij = s_ij (x_i - x_j), s_ij = W'(r)/r from the
// density pass (NeighborLists::slopes). Every float operation is in a fixed order: the results
// do not depend on the number of threads.
#pragma once

#include "sim/neighbor_grid.h"
#include "sim/particles.h"
#include "sim/solvers/pressure_solver.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace kurage::sim::solvers {

using Float4 = float __attribute__((vector_size(16)));

// f(i) for every particle, in parallel (each i independent).
template <class F>
void forEach(size_t count, F&& f) {
  tbb::parallel_for(tbb::blocked_range<size_t>(0, count, 4096), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) f(i);
  });
}

// The sum over particles of f(i), per fixed chunk (NeighborLists::kChunk) and then over chunks in
// order; `partial` is scratch.
template <class F>
double orderedSum(size_t count, std::vector<double>& partial, F&& f) {
  const size_t chunks = (count + NeighborLists::kChunk - 1) / NeighborLists::kChunk;
  partial.assign(chunks, 0.0);
  tbb::parallel_for(size_t(0), chunks, [&](size_t c) {
    double s = 0.0;
    const size_t last = std::min(count, (c + 1) * NeighborLists::kChunk);
    for (size_t i = c * NeighborLists::kChunk; i < last; ++i) s += f(i);
    partial[c] = s;
  });
  double total = 0.0;
  for (double s : partial) total += s;
  return total;
}

// byId[p.id[i]] = values[i], sized to the largest id + 1 (0 for ids no particle has): a warm
// start kept by id, since sorting reorders the particles.
inline void storeById(const ParticleSet& p, const std::vector<float>& values, std::vector<float>& byId) {
  const int64_t maxId = tbb::parallel_reduce(
      tbb::blocked_range<size_t>(0, p.size(), 4096), int64_t(-1),
      [&](const tbb::blocked_range<size_t>& r, int64_t m) {
        for (size_t i = r.begin(); i != r.end(); ++i) m = std::max(m, p.id[i]);
        return m;
      },
      [](int64_t a, int64_t b) { return std::max(a, b); });
  byId.assign(size_t(maxId + 1), 0.0f);
  forEach(p.size(), [&](size_t i) { byId[size_t(p.id[i])] = values[i]; });  // ids are unique
}

// f(i, s) for every particle i, in parallel by the neighbour lists' chunks, s pointing at its first
// neighbour's W'(r)/r.
template <class F>
void forEachWithSlopes(const NeighborLists& neighbors, size_t count, F&& f) {
  tbb::parallel_for(size_t(0), neighbors.chunkCount(), [&](size_t ch) {
    const size_t last = std::min(count, (ch + 1) * NeighborLists::kChunk);
    const float* s0 = neighbors.slopes(ch).data();
    for (size_t i = ch * NeighborLists::kChunk; i < last; ++i) f(i, s0 + neighbors.offset(i));
  });
}

// sum_j w_j (v_i - v_j) grad W_ij per axis (the density rate's neighbour sum before its three
// axes are added), over neighbours [begin, end) with slopes from `slope`.
inline Float4 rateSum(const uint32_t* begin, const uint32_t* end, const float* slope, const Float4* x, const Float4* v,
                      Float4 xi, Float4 vi) {
  Float4 sum = {0.0f, 0.0f, 0.0f, 0.0f};
  for (const uint32_t* it = begin; it != end; ++it, ++slope) {
    const Float4 xj = x[*it];
    sum += xj[3] * ((vi - v[*it]) * (*slope * (xi - xj)));  // w_j (v_i - v_j) * grad W_ij, per axis
  }
  return sum;
}

// sum_j w_j (k_i + k_j) grad W_ij (a symmetric pressure push's neighbour sum; fourth lane
// meaningless), the scalars multiplied first.
inline Float4 pushSum(const uint32_t* begin, const uint32_t* end, const float* slope, const Float4* x, const float* k,
                      Float4 xi, float ki) {
  Float4 a = {0.0f, 0.0f, 0.0f, 0.0f};
  for (const uint32_t* it = begin; it != end; ++it, ++slope) {
    const uint32_t j = *it;
    const Float4 xj = x[j];
    a += (*slope * (xj[3] * (ki + k[j]))) * (xi - xj);
  }
  return a;
}

// The corrected kernel gradient's neighbour sums (DFSPH with fluid.gradient_correction; its header
// has the equations), L_i's rows applied by the caller. Fourth lanes meaningless.
// Density rate: t[a] = sum_j (v_i - v_j)_a (w_j s_ij) (x_i - x_j), so that the rate is sum_a L_i,a . t[a].
inline void correctedRateSum(const uint32_t* begin, const uint32_t* end, const float* slope, const Float4* x,
                             const Float4* v, Float4 xi, Float4 vi, Float4 t[3]) {
  Float4 t0 = {0.0f, 0.0f, 0.0f, 0.0f}, t1 = t0, t2 = t0;
  for (const uint32_t* it = begin; it != end; ++it, ++slope) {
    const Float4 xj = x[*it];
    const Float4 dv = vi - v[*it];
    const Float4 e = (xj[3] * *slope) * (xi - xj);
    t0 += dv[0] * e; t1 += dv[1] * e; t2 += dv[2] * e;
  }
  t[0] = t0; t[1] = t1; t[2] = t2;
}

// Factor: plain = sum_j w_j s_ij (x_i - x_j) (the uncorrected gradient sum) and
// S = sum_j c_j |L_i s_ij (x_i - x_j)|^2, L_i's three rows at `rows`.
inline void correctedFactorSum(const uint32_t* begin, const uint32_t* end, const float* slope, const Float4* x,
                               const float* response, Float4 xi, const Float4* rows, Float4& plain, float& S) {
  plain = Float4{0.0f, 0.0f, 0.0f, 0.0f};
  S = 0.0f;
  for (const uint32_t* it = begin; it != end; ++it, ++slope) {
    const uint32_t j = *it;
    const Float4 d = *slope * (xi - x[j]);
    const Float4 grad = rows[0] * d[0] + rows[1] * d[1] + rows[2] * d[2];  // L_i grad W_ij
    plain += x[j][3] * d;
    const Float4 g2 = grad * grad;
    S += response[j] * (g2[0] + g2[1] + g2[2]);
  }
}

// Push: m0 = sum_j s_ij terms[2j], m1 = sum_j s_ij terms[2j + 1], y2 = sum_j s_ij z[j] (the
// neighbours' packed w_j k_j L_j and w_j k_j L_j x_j; DFSPH's applyPressure).
inline void correctedPushSum(const uint32_t* begin, const uint32_t* end, const float* slope, const Float4* terms,
                             const float* z, Float4& m0, Float4& m1, float& y2) {
  m0 = Float4{0.0f, 0.0f, 0.0f, 0.0f};
  m1 = m0;
  y2 = 0.0f;
  for (const uint32_t* it = begin; it != end; ++it, ++slope) {
    const Float4* t = terms + 2 * size_t(*it);
    const float s = *slope;
    m0 += s * t[0]; m1 += s * t[1]; y2 += s * z[*it];
  }
}

// The neighbours a relaxed Jacobi iteration of relaxation w is measured for: those of a particle
// inside a full lattice of the fluid spacing at support radius h (in spacings), at most 26 (the
// count at h = 2 l). A relaxed Jacobi iteration's largest eigenvalue grows with the neighbour
// count: a particle with more neighbours (a body at half the fluid spacing has about 8 times as
// many; a wider support 92 at h = 3 l) iterates with w min(1, this / its count).
inline float relaxedNeighbours(float supportRadius) {
  float count = 0.0f;
  const int reach = int(std::ceil(supportRadius));
  for (int a = -reach; a <= reach; ++a)
    for (int b = -reach; b <= reach; ++b)
      for (int c = -reach; c <= reach; ++c)
        if ((a || b || c) && float(a * a + b * b + c * c) < supportRadius * supportRadius) count += 1.0f;
  return std::min(count, 26.0f);
}

// One iterative solve's figures over a run (run.json's "<solve>.*" keys; checkpointed as bytes):
// iterations summed and the most in one step, the steps that stopped at the cap, and the final
// mean error (fraction of rho0) of the last step, summed over steps and the largest.
struct SolveStats {
  uint64_t iterations = 0;
  int maxIterations = 0;
  uint64_t capHits = 0;
  double lastError = 0.0;
  double sumError = 0.0;
  double maxError = 0.0;
  void record(int stepIterations, double error, bool capped) {  // once a step that solves
    iterations += uint64_t(stepIterations);
    maxIterations = std::max(maxIterations, stepIterations);
    if (capped) ++capHits;
    lastError = error;
    sumError += error;
    maxError = std::max(maxError, error);
  }
  // `steps`: the solver's steps (the means' divisor); `tolerance` a fraction of rho0.
  void report(SolverReport& out, const std::string& solve, uint64_t steps, int cap, double tolerance) const {
    const double n = std::max<double>(1.0, double(steps));
    out.add(solve + ".mean_iterations", double(iterations) / n);
    out.add(solve + ".max_iterations", maxIterations);
    out.add(solve + ".cap", cap);
    out.add(solve + ".cap_hits", capHits);
    out.add(solve + ".final_error", lastError);
    out.add(solve + ".mean_final_error", sumError / n);
    out.add(solve + ".max_final_error", maxError);
    out.add(solve + ".tolerance", tolerance);
  }
};

// Telescopic body particles torn (their rest density below a quarter of its initial value,
// BodySystem::kTornDensityRatio) and so left out of a solver's unknowns: the steps that had any and
// the most at once (run.json's torn_body_particles, and a warning).
struct TornCount {
  uint64_t steps = 0;
  int most = 0;
  void count(const uint8_t* unsolved, size_t n) {  // once a step
    if (!unsolved) return;
    const auto torn = std::count(unsolved, unsolved + n, uint8_t(kTorn));
    if (torn > 0) ++steps;
    most = std::max(most, int(torn));
  }
  void report(SolverReport& out) const {
    out.add("torn_body_particles.steps", steps);
    out.add("torn_body_particles.max_at_once", most);
    out.add("torn_body_particles.note", "telescopic body particles stretched until their rest density fell below a "
                                        "quarter of its initial value, left out of the solves' unknowns "
                                        "(docs/design/physics.md, Bodies under DFSPH)");
  }
  void warn(std::vector<SolverWarning>& out, std::string_view solver, uint64_t solverSteps) const {
    if (steps == 0) return;
    out.push_back({"in " + std::to_string(steps) + " of " + std::to_string(solverSteps) + " steps (up to " +
                       std::to_string(most) +
                       " at once) telescopic body particles were stretched below a quarter of their rest density "
                       "and left out of the " + std::string(solver) + " solver's unknowns",
                   "torn_body_particles"});
  }
};

}  // namespace kurage::sim::solvers
