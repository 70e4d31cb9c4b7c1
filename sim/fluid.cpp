#include "sim/fluid.h"

#include "sim/solvers/sweeps.h"

#include <Eigen/LU>
#include <immintrin.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cassert>
#include <cstring>
#include <type_traits>
#include <cmath>

namespace kurage::sim {

namespace {
#if defined(__SSE2__)
// Four floats (or ints) in one SSE register (GCC and Clang vector extension)
using Float4 = float __attribute__((vector_size(16)));
using Int4 = int __attribute__((vector_size(16)));
#endif

#if defined(__SSE2__)
// The cubic spline's W(r) and W'(r) / r (0 at r <= 1e-6 h) for the four neighbours whose r^2 bits
// are bits[0..3]: CubicSplineKernel's operator() and derivative() lane by lane, both branches
// computed and the lane's one kept. The same operations in the same order as the scalar loop,
// each correctly rounded, so the same floats (KURAGE_NATIVE's FMA may contract the two
// differently). Measured on bench sim's 100k dam break under DFSPH: the branch on q <= 1/2, taken
// by one neighbour in eight at random, and a square root and a division a neighbour one at a time
// made this pass 2.5 times the paper's poly6 pass.
inline void cubicFour(const CubicSplineKernel& k, const uint32_t* bits, Float4& w, Float4& slope) {
  Float4 r2;
  std::memcpy(&r2, bits, sizeof r2);
  const Float4 r = Float4(_mm_sqrt_ps(__m128(r2)));
  const Float4 q = r * k.invH;
  const Float4 t = 1.0f - q;
  const Int4 outside = q >= 1.0f, inner = q <= 0.5f, tiny = r <= 1e-6f * k.h;
  const auto pick = [](Int4 m, Float4 a, Float4 b) { return Float4((m & Int4(a)) | (~m & Int4(b))); };
  const Float4 wInner = k.sigma * (6.0f * q * q * (q - 1.0f) + 1.0f);
  const Float4 wOuter = k.sigma * 2.0f * t * t * t;
  w = Float4(~outside & Int4(pick(inner, wInner, wOuter)));
  const Float4 dInner = k.sigma * k.invH * q * (18.0f * q - 12.0f);
  const Float4 dOuter = -6.0f * k.sigma * k.invH * t * t;
  slope = Float4(~(outside | tiny) & Int4(pick(inner, dInner, dOuter) / r));
}
#endif

// Poly6 with the paper's arithmetic (no square root); other kernels through fromSquared().
template <DensitySum Form, class Kernel>
void densityPass(const NeighborGrid& grid, ParticleSet& particles, const Kernel& kernel,
                 NeighborLists& neighbors, const WallSums& walls, const float* boundaryVolume) {
  constexpr bool isPoly6 = std::is_same_v<Kernel, Poly6Kernel>;
  const size_t count = particles.size();
  const float* x = particles.x.data();
  const float* y = particles.y.data();
  const float* z = particles.z.data();
  const float* m = particles.mass.data();
  const float* rho0 = particles.restDensity.data();
  float* rho = particles.density.data();
  const float h2 = kernel.h2;
  const std::vector<uint32_t>& cells = grid.cellOfSorted();
  neighbors.resize(count);
  const auto sift = solvers::sweepTable().sift;  // KURAGE_SIMD's (sweeps.h)
  // One task per chunk of particles: the chunk's neighbour buffer is filled in particle order.
  tbb::parallel_for(size_t(0), neighbors.chunkCount(), [&](size_t c) {
    std::vector<uint32_t>& buffer = neighbors.chunk(c);
    buffer.clear();
    std::array<std::array<uint32_t, 2>, 9> ranges;
    std::array<uint32_t, 1024> local;
    std::vector<uint32_t>& overflow = neighbors.scratch(c);
    const size_t last = std::min(count, (c + 1) * NeighborLists::kChunk);
    for (size_t i = c * NeighborLists::kChunk; i < last; ++i) {
      const float xi = x[i], yi = y[i], zi = z[i];
      const int n = grid.candidateRanges(cells[i], ranges);
      size_t candidates = 0;
      for (int r = 0; r < n; ++r) candidates += ranges[r][1] - ranges[r][0];
      const size_t begin = buffer.size();
      buffer.resize(begin + candidates);  // capacity is kept between steps
      uint32_t* out = buffer.data() + begin;
      size_t found = 0;
      auto weight = [&](uint32_t j) { return Form == DensitySum::Mass ? m[j] : m[j] / rho0[j]; };
      // the particle itself, r = 0
      float sum = isPoly6 ? weight(uint32_t(i)) * h2 * h2 * h2 : weight(uint32_t(i)) * kernel.fromSquared(0.0f);
      // First the candidates are sifted (SweepTable::sift: every one is written, the count advances
      // only for a neighbour), then the neighbours' weights are summed in order (the same sum as in
      // one pass with a branch per candidate, without the branch's mispredictions, for either
      // kernel). Their r^2 is kept on the stack, unless there are unusually many (a scratch buffer
      // per chunk then).
      if (candidates > local.size() && overflow.size() < candidates) overflow.resize(candidates);
      uint32_t* d2 = candidates > local.size() ? overflow.data() : local.data();
      found = sift(x, y, z, xi, yi, zi, h2, uint32_t(i), ranges.data(), n, out);
      for (size_t k = 0; k < found; ++k) {  // the neighbours' r^2 again: the sift's floats
        const uint32_t j = out[k];
        const float dx = x[j] - xi, dy = y[j] - yi, dz = z[j] - zi;
        d2[k] = std::bit_cast<uint32_t>(dx * dx + dy * dy + dz * dz);
      }
      if constexpr (isPoly6) {
        for (size_t k = 0; k < found; ++k) {
          const float t = h2 - std::bit_cast<float>(d2[k]);
          sum += weight(out[k]) * t * t * t;
        }
      } else {
        // Each neighbour's W'(r)/r is kept alongside its entry for DFSPH's gradients (the same
        // floats its factor pass computed from the positions: the solves do not move them).
        std::vector<float>& slopes = neighbors.slopes(c);
        slopes.resize(begin + found);  // capacity is kept between steps
        float* slope = slopes.data() + begin;
        size_t k = 0;
#if defined(__SSE2__)
        for (; k + 4 <= found; k += 4) {
          Float4 w, s;
          cubicFour(kernel, d2 + k, w, s);
          const Float4 terms = Float4{weight(out[k]), weight(out[k + 1]), weight(out[k + 2]), weight(out[k + 3])} * w;
          sum += terms[0]; sum += terms[1]; sum += terms[2]; sum += terms[3];  // in order, as below
          std::memcpy(slope + k, &s, sizeof s);
        }
#endif
        for (; k < found; ++k) {
          const float r = std::sqrt(std::bit_cast<float>(d2[k]));
          sum += weight(out[k]) * kernel(r);
          slope[k] = r > 1e-6f * kernel.h ? kernel.derivative(r) / r : 0.0f;
        }
      }
      buffer.resize(begin + found);
      neighbors.setRange(i, uint32_t(begin), uint32_t(buffer.size()));
      const float scale = Form == DensitySum::Mass ? 1.0f : rho0[i];
      if constexpr (isPoly6) rho[i] = scale * kernel.coefficient * sum;  // (3), the paper's kernel
      else rho[i] = scale * sum;
      if (walls.weights)
        rho[i] += (Form == DensitySum::Mass ? 1.0f : rho0[i] / walls.restDensity) *
                  boxWallContribution(*walls.weights, walls.box, kernel.h, xi, yi, zi).density;
      if (boundaryVolume) rho[i] += rho0[i] * boundaryVolume[i];  // Akinci 2012, eq. 4
    }
  });
}
}  // namespace

void computeDensity(const NeighborGrid& grid, ParticleSet& particles, const Poly6Kernel& poly6,
                    NeighborLists& neighbors, const WallSums& walls, DensitySum form, const float* boundaryVolume) {
  if (form == DensitySum::Mass) densityPass<DensitySum::Mass>(grid, particles, poly6, neighbors, walls, boundaryVolume);
  else densityPass<DensitySum::Volume>(grid, particles, poly6, neighbors, walls, boundaryVolume);
}

void computeDensity(const NeighborGrid& grid, ParticleSet& particles, const CubicSplineKernel& cubic,
                    NeighborLists& neighbors, const WallSums& walls, DensitySum form, const float* boundaryVolume) {
  if (form == DensitySum::Mass) densityPass<DensitySum::Mass>(grid, particles, cubic, neighbors, walls, boundaryVolume);
  else densityPass<DensitySum::Volume>(grid, particles, cubic, neighbors, walls, boundaryVolume);
}

void computePressure(ParticleSet& particles, float pressureStiffness, NegativePressure negativePressure) {
  const size_t n = particles.size();
  const float* rho = particles.density.data();
  const float* rho0 = particles.restDensity.data();
  float* p = particles.pressure.data();
  const bool clamp = negativePressure == NegativePressure::Clamp;
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 8192), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) {
      const float value = pressureStiffness * (rho[i] - rho0[i]);  // (4)
      p[i] = clamp ? std::max(value, 0.0f) : value;
    }
  });
}

namespace {

// The walls' penalty on a fluid particle under WCSPH with boundary particles (WallSums), per unit mass.
inline Eigen::Vector3f wallPenalty(const WallSums& walls, float px, float py, float pz) {
  const float rest = walls.penaltyRest, k = walls.penaltyStiffness;
  const Eigen::Vector3f q(px, py, pz);
  const Eigen::Vector3f below = (walls.box.min + Eigen::Vector3f::Constant(rest) - q).cwiseMax(0.0f);
  const Eigen::Vector3f above = (q - walls.box.max + Eigen::Vector3f::Constant(rest)).cwiseMax(0.0f);
  return k * (below - above);
}

// dist[k] = |r_i - r_j| and inv[k] = 1 / dist[k] for the neighbours j = nb[k]: the
// force pass's square root and division, four neighbours at a time where SSE2 is available (each
// correctly rounded, the same floats as one at a time). Coincident pairs get inf, unused.
void distanceAndInverse(const float* x, const float* y, const float* z, float xi, float yi, float zi,
                        const uint32_t* nb, size_t count, float* dist, float* inv) {
  size_t k = 0;
#if defined(__SSE2__)
  for (; k + 4 <= count; k += 4) {
    const uint32_t a = nb[k], b = nb[k + 1], c = nb[k + 2], d = nb[k + 3];
    const Float4 dx = Float4{xi, xi, xi, xi} - Float4{x[a], x[b], x[c], x[d]};
    const Float4 dy = Float4{yi, yi, yi, yi} - Float4{y[a], y[b], y[c], y[d]};
    const Float4 dz = Float4{zi, zi, zi, zi} - Float4{z[a], z[b], z[c], z[d]};
    const Float4 r = Float4(_mm_sqrt_ps(__m128(dx * dx + dy * dy + dz * dz)));
    const Float4 q = 1.0f / r;
    std::memcpy(dist + k, &r, sizeof r);
    std::memcpy(inv + k, &q, sizeof q);
  }
#endif
  for (; k < count; ++k) {
    const uint32_t j = nb[k];
    const float dx = xi - x[j], dy = yi - y[j], dz = zi - z[j];
    dist[k] = std::sqrt(dx * dx + dy * dy + dz * dz);
    inv[k] = 1.0f / dist[k];
  }
}

template <PressureForce Form, bool Pressure, bool Cubic>
void accelerate(const NeighborLists& neighbors, ParticleSet& particles, GradientKernel kernel,
                const ViscosityKernel& viscosity, float dynamicViscosity, const Eigen::Vector3f& gravity,
                const WallSums& walls, const float* correction, const float* boundaryGradient,
                ViscosityLanes* lanes = nullptr) {
  const float* x = particles.x.data();
  const float* y = particles.y.data();
  const float* z = particles.z.data();
  const float* vx = particles.vx.data();
  const float* vy = particles.vy.data();
  const float* vz = particles.vz.data();
  const float* m = particles.mass.data();
  const float* rho = particles.density.data();
  const float* p = particles.pressure.data();
  const int64_t* id = particles.id.data();
  const int* kind = particles.kind.data();
  float* ax = particles.ax.data();
  float* ay = particles.ay.data();
  float* az = particles.az.data();
  const float h = kernel.spiky->h;
  // The spiky gradient and the viscosity Laplacian share the factor 45 / (pi h^6); the cubic
  // spline's -dW/dr is summed with its own coefficient.
  const float gradC = Cubic ? 1.0f : kernel.spiky->gradientCoefficient;
  const bool penalty = walls.penaltyStiffness > 0.0f;
  const float lapC = viscosity.laplacianCoefficient * dynamicViscosity;
  const float tiny2 = 1e-12f * h * h;
  // a_i from particle i's neighbour sums: the walls' terms added, over rho_i, plus gravity
  const auto finish = [&](size_t i, float fpx, float fpy, float fpz, float fvx, float fvy,
                          float fvz) __attribute__((always_inline)) {  // inlined in both loops below
    const float xi = x[i], yi = y[i], zi = z[i];
    const float pi = p[i];
    const float rhoI = rho[i];
    const float piOverRho2 = pi / (rhoI * rhoI);
    float wx = 0, wy = 0, wz = 0;  // wall pressure force density
    if (Pressure && boundaryGradient) {
      // Boundary particles: psi_b = rho0_i V_b, rho_b = rho0_i (Akinci 2012, eq. 10). A body
      // particle's walls carry its own pressure, p_b = p_i (mirrored); a fluid particle's carry
      // none (p_b = 0), the rest of their push being the penalty below (header).
      const float rho0i = particles.restDensity[i];
      const float pb = kind[i] != 0 || !penalty ? pi : 0.0f;
      float factor;
      if constexpr (Form == PressureForce::Mueller2003) factor = 0.5f * (pi + pb);  // sum psi (p_i + p_b) / (2 rho_b)
      else factor = rhoI * rho0i * (piOverRho2 + pb / (rho0i * rho0i));
      wx -= factor * boundaryGradient[3 * i];
      wy -= factor * boundaryGradient[3 * i + 1];
      wz -= factor * boundaryGradient[3 * i + 2];
    }
    if (Pressure && penalty && kind[i] == 0) {
      const Eigen::Vector3f push = rhoI * wallPenalty(walls, xi, yi, zi);  // a force density, like the others
      wx += push.x(); wy += push.y(); wz += push.z();
    }
    if (Pressure && walls.weights) {
      // Virtual wall particles: rest density rho0, the pressure of particle i (mirror).
      const WallContribution c = boxWallContribution(*walls.weights, walls.box, h, xi, yi, zi);
      float factor;
      if constexpr (Form == PressureForce::Mueller2003) factor = pi / walls.restDensity;
      else factor = rhoI * (piOverRho2 + pi / (walls.restDensity * walls.restDensity));
      wx += factor * c.gradient.x(); wy += factor * c.gradient.y(); wz += factor * c.gradient.z();
    }
    const float invRho = 1.0f / rhoI;
    ax[i] = (gradC * fpx + wx + lapC * fvx) * invRho + gravity.x();
    ay[i] = (gradC * fpy + wy + lapC * fvy) * invRho + gravity.y();
    az[i] = (gradC * fpz + wz + lapC * fvz) * invRho + gravity.z();
  };
  if (!Pressure && lanes && lanes->lists) {
    // Eight particles at a time on the solver's interleaved lists (sweeps.h, the lanes path; the
    // same floats): first each particle's records (x, y, z, m / rho) and (vx, vy, vz, 0).
    const size_t n = particles.size();
    lanes->x.resize(n);
    lanes->v.resize(n);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 4096), [&](const tbb::blocked_range<size_t>& r) {
      for (size_t i = r.begin(); i != r.end(); ++i) {
        lanes->x[i] = Float4{x[i], y[i], z[i], m[i] / rho[i]};
        lanes->v[i] = Float4{vx[i], vy[i], vz[i], 0.0f};
      }
    });
    const solvers::LaneLists& lists = *lanes->lists;
    const auto sum = solvers::sweepTable(solvers::SweepIsa::Lanes).viscosityLanes;
    tbb::parallel_for(size_t(0), lists.rows.size(), [&](size_t ch) {
      for (size_t gi = lists.groupsBegin(ch); gi < lists.groupsEnd(ch); ++gi) {
        const solvers::LaneGroup& g = lists.groups[gi];
        Float4 fv[solvers::LaneLists::kWidth];
        sum(lists.rows[ch].data(), g, lanes->x.data(), lanes->v.data(), h, tiny2, fv);
        for (uint32_t l = 0; l < g.used; ++l) finish(g.self[l], 0.0f, 0.0f, 0.0f, fv[l][0], fv[l][1], fv[l][2]);
      }
    });
    return;
  }
  tbb::parallel_for(tbb::blocked_range<size_t>(0, particles.size(), 512), [&](const tbb::blocked_range<size_t>& range) {
    // |r_ij| and 1 / |r_ij| of one particle's neighbours, on the stack (the step allocates
    // nothing: StepLoop.AllocatesNothingOnceRunning); a particle with more neighbours takes them
    // one at a time.
    constexpr size_t kPacked = 256;
    std::array<float, 2 * kPacked> lengths;
    for (size_t i = range.begin(); i != range.end(); ++i) {
      const float xi = x[i], yi = y[i], zi = z[i];
      const float vxi = vx[i], vyi = vy[i], vzi = vz[i];
      const float pi = p[i];
      const float rhoI = rho[i];
      const float piOverRho2 = pi / (rhoI * rhoI);
      float fpx = 0, fpy = 0, fpz = 0;  // pressure force density / (45 / (pi h^6))
      float fvx = 0, fvy = 0, fvz = 0;  // viscosity force density / (mu 45 / (pi h^6))
      // The cubic spline's W'(r)/r per neighbour, kept by the density pass (NeighborLists::slopes)
      const float* slope = Cubic ? neighbors.slopes(i / NeighborLists::kChunk).data() + neighbors.offset(i) : nullptr;
      // With pressure, first |r_ij| and 1 / |r_ij| for all neighbours, four at a time: one at a
      // time, each pair waited on its square root and division (the same floats).
      // (Viscosity alone, DFSPH's, ran no faster so: its pairs need no division.)
      const bool packed = Pressure && neighbors.count(i) <= kPacked;
      if (packed)
        distanceAndInverse(x, y, z, xi, yi, zi, neighbors.begin(i), neighbors.count(i), lengths.data(),
                           lengths.data() + kPacked);
      size_t k = 0;  // the neighbour's place in the list (and in lengths)
      for (const uint32_t* it = neighbors.begin(i); it != neighbors.end(i); ++it, ++k) {
        const uint32_t j = *it;
        const float slopeJ = Cubic ? *slope++ : 0.0f;
        // r_vec = r_i - r_j
        const float dx = xi - x[j], dy = yi - y[j], dz = zi - z[j];
        const float r2 = dx * dx + dy * dy + dz * dz;
        const float mOverRho = m[j] / rho[j];
        float ux, uy, uz, dist;
        if (r2 > tiny2) {
          dist = packed ? lengths[k] : std::sqrt(r2);
          const float inv = packed ? lengths[kPacked + k] : 1.0f / dist;
          ux = dx * inv; uy = dy * inv; uz = dz * inv;
        } else {  // coincident particles: separate them along x, ordered by id
          dist = 0.0f;
          ux = id[i] < id[j] ? -1.0f : 1.0f; uy = 0.0f; uz = 0.0f;
        }
        const float t = h - dist;
        // (6): mu m_j (v_j - v_i) / rho_j * 45/(pi h^6) (h - r)
        const float visc = mOverRho * t;
        fvx += visc * (vx[j] - vxi); fvy += visc * (vy[j] - vyi); fvz += visc * (vz[j] - vzi);
        if constexpr (!Pressure) continue;
        float press;
        if constexpr (Form == PressureForce::Mueller2003)
          // (5): -m_j (p_i + p_j) / (2 rho_j) * grad W
          press = 0.5f * mOverRho * (pi + p[j]);
        else  // rho_i m_j (p_i / rho_i^2 + p_j / rho_j^2) |grad W|
          press = rhoI * m[j] * (piOverRho2 + p[j] / (rho[j] * rho[j]));
        // times -dW/dr over the gradient's coefficient: the cubic spline's own, or (h - r)^2 for
        // the spiky kernel (multiplied in this order, the paper's scenes keep their floats)
        if constexpr (Cubic) press *= -slopeJ * dist;
        else press = press * t * t;
        if (correction) {
          // (L_i + L_j) / 2 applied to the direction: Bonet & Lok's corrected, symmetrised gradient.
          const float* a = correction + 6 * i;
          const float* b = correction + 6 * size_t(j);
          const float xx = 0.5f * (a[0] + b[0]), yy = 0.5f * (a[1] + b[1]), zz = 0.5f * (a[2] + b[2]);
          const float xy = 0.5f * (a[3] + b[3]), xz = 0.5f * (a[4] + b[4]), yz = 0.5f * (a[5] + b[5]);
          const float cx = xx * ux + xy * uy + xz * uz, cy = xy * ux + yy * uy + yz * uz, cz = xz * ux + yz * uy + zz * uz;
          ux = cx; uy = cy; uz = cz;
        }
        fpx += press * ux; fpy += press * uy; fpz += press * uz;
      }
      finish(i, fpx, fpy, fpz, fvx, fvy, fvz);
    }
  });
}

}  // namespace

void computeFluidAcceleration(const NeighborLists& neighbors, ParticleSet& particles, GradientKernel kernel,
                              const ViscosityKernel& viscosity, float dynamicViscosity,
                              const Eigen::Vector3f& gravity, PressureForce form, const WallSums& walls,
                              const float* correction, bool pressure, const float* boundaryGradient,
                              ViscosityLanes* lanes) {
  const bool cubic = kernel.cubic != nullptr;
  if (!pressure)
    accelerate<PressureForce::Monaghan1992, false, false>(neighbors, particles, kernel, viscosity, dynamicViscosity,
                                                          gravity, walls, nullptr, nullptr, lanes);
  else if (form == PressureForce::Mueller2003 && cubic)
    accelerate<PressureForce::Mueller2003, true, true>(neighbors, particles, kernel, viscosity, dynamicViscosity,
                                                       gravity, walls, nullptr, boundaryGradient);
  else if (form == PressureForce::Mueller2003)
    accelerate<PressureForce::Mueller2003, true, false>(neighbors, particles, kernel, viscosity, dynamicViscosity,
                                                        gravity, walls, nullptr, boundaryGradient);
  else if (cubic)
    accelerate<PressureForce::Monaghan1992, true, true>(neighbors, particles, kernel, viscosity, dynamicViscosity,
                                                        gravity, walls, correction, boundaryGradient);
  else
    accelerate<PressureForce::Monaghan1992, true, false>(neighbors, particles, kernel, viscosity, dynamicViscosity,
                                                         gravity, walls, correction, boundaryGradient);
}

void computeGradientCorrection(const NeighborLists& neighbors, const ParticleSet& particles, GradientKernel kernel,
                               const ContainerParams& box, std::vector<float>& correction) {
  const size_t n = particles.size();
  correction.resize(6 * n);
  const float h = kernel.spiky->h;
  const float* x = particles.x.data();
  const float* y = particles.y.data();
  const float* z = particles.z.data();
  std::vector<float> volume(n);  // V_j = m_j / rho_j, once a particle rather than once a pair
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 4096), [&](const tbb::blocked_range<size_t>& range) {
    for (size_t i = range.begin(); i != range.end(); ++i) volume[i] = particles.mass[i] / particles.density[i];
  });
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 512), [&](const tbb::blocked_range<size_t>& range) {
    for (size_t i = range.begin(); i != range.end(); ++i) {
      float* out = correction.data() + 6 * i;
      out[0] = out[1] = out[2] = 1.0f;
      out[3] = out[4] = out[5] = 0.0f;
      const Eigen::Vector3f p(x[i], y[i], z[i]);
      if (((p - box.min).array() < h).any() || ((box.max - p).array() < h).any()) continue;
      float xx = 0.0f, yy = 0.0f, zz = 0.0f, xy = 0.0f, xz = 0.0f, yz = 0.0f;  // M is symmetric
      // The cubic spline's W'(r)/r as the density pass stored it (NeighborLists::slopes; 0 for
      // coincident particles); the spiky kernel's from r.
      const size_t chunk = i / NeighborLists::kChunk;
      assert(!kernel.cubic || neighbors.slopes(chunk).size() == neighbors.chunkSize(chunk));
      const float* slope = kernel.cubic ? neighbors.slopes(chunk).data() + neighbors.offset(i) : nullptr;
      for (const uint32_t* it = neighbors.begin(i); it != neighbors.end(i); ++it) {
        const uint32_t j = *it;
        const float dx = x[i] - x[j], dy = y[i] - y[j], dz = z[i] - z[j];
        float weight;  // V_j (-dW/dr / r)
        if (slope) {
          weight = volume[j] * -*slope++;
        } else {
          const float r = std::sqrt(dx * dx + dy * dy + dz * dz);
          if (r <= 1e-6f * h) continue;
          weight = volume[j] * -kernel.spiky->derivative(r) / r;
        }
        const float wx = weight * dx, wy = weight * dy;
        xx += wx * dx; yy += wy * dy; zz += weight * dz * dz;
        xy += wx * dy; xz += wx * dz; yz += wy * dz;
      }
      Eigen::Matrix3f M;
      M << xx, xy, xz, xy, yy, yz, xz, yz, zz;
      if (!(M.determinant() > 0.25f)) continue;
      const Eigen::Matrix3f L = M.inverse();
      out[0] = L(0, 0); out[1] = L(1, 1); out[2] = L(2, 2);
      out[3] = L(0, 1); out[4] = L(0, 2); out[5] = L(1, 2);
    }
  });
}

float calibratedParticleMass(float spacing, float supportRadius, float restDensity, DensityKernel kernel) {
  const Poly6Kernel poly6(supportRadius);
  const CubicSplineKernel cubic(supportRadius);
  const int reach = static_cast<int>(std::ceil(supportRadius / spacing));
  double sum = 0.0;
  for (int k = -reach; k <= reach; ++k)
    for (int j = -reach; j <= reach; ++j)
      for (int i = -reach; i <= reach; ++i) {
        const double r2 = double(spacing) * spacing * (i * i + j * j + k * k);
        sum += kernel == DensityKernel::Poly6 ? poly6.fromSquared(float(r2)) : cubic.fromSquared(float(r2));
      }
  return float(restDensity / sum);
}

}  // namespace kurage::sim
