#include "sim/fluid.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

namespace kurage::sim {

void computeDensity(const NeighborGrid& grid, ParticleSet& particles, const Poly6Kernel& poly6,
                    NeighborLists& neighbors, const WallSums& walls) {
  const size_t count = particles.size();
  const float* x = particles.x.data();
  const float* y = particles.y.data();
  const float* z = particles.z.data();
  const float* m = particles.mass.data();
  float* rho = particles.density.data();
  const float h2 = poly6.h2;
  const std::vector<uint32_t>& cells = grid.cellOfSorted();
  neighbors.resize(count);
  // One task per chunk of particles: the chunk's neighbour buffer is filled in particle order.
  tbb::parallel_for(size_t(0), neighbors.chunkCount(), [&](size_t c) {
    std::vector<uint32_t>& buffer = neighbors.chunk(c);
    buffer.clear();
    std::array<std::array<uint32_t, 2>, 9> ranges;
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
      float sum = m[i] * h2 * h2 * h2;  // the particle itself, r = 0
      for (int r = 0; r < n; ++r)
        for (uint32_t j = ranges[r][0]; j < ranges[r][1]; ++j) {
          const float dx = x[j] - xi, dy = y[j] - yi, dz = z[j] - zi;
          const float r2 = dx * dx + dy * dy + dz * dz;
          if (r2 >= h2 || j == i) continue;
          const float t = h2 - r2;
          sum += m[j] * t * t * t;
          out[found++] = j;
        }
      buffer.resize(begin + found);
      neighbors.setRange(i, uint32_t(begin), uint32_t(buffer.size()));
      rho[i] = poly6.coefficient * sum;  // (3)
      if (walls.weights) rho[i] += boxWallContribution(*walls.weights, walls.box, poly6.h, xi, yi, zi).density;
    }
  });
}

void computePressure(ParticleSet& particles, float pressureStiffness, NegativePressure negativePressure) {
  const size_t n = particles.size();
  const float* rho = particles.density.data();
  const float* rho0 = particles.restDensity.data();
  float* p = particles.pressure.data();
  const bool clamp = negativePressure == NegativePressure::Clamp;
  for (size_t i = 0; i < n; ++i) {
    const float value = pressureStiffness * (rho[i] - rho0[i]);  // (4)
    p[i] = clamp ? std::max(value, 0.0f) : value;
  }
}

namespace {

template <PressureForce Form>
void accelerate(const NeighborLists& neighbors, ParticleSet& particles, const SpikyKernel& spiky,
                const ViscosityKernel& viscosity, float dynamicViscosity, const Eigen::Vector3f& gravity,
                const WallSums& walls) {
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
  float* ax = particles.ax.data();
  float* ay = particles.ay.data();
  float* az = particles.az.data();
  const float h = spiky.h;
  // Both kernels share the factor 45 / (pi h^6).
  const float gradC = spiky.gradientCoefficient;
  const float lapC = viscosity.laplacianCoefficient * dynamicViscosity;
  const float tiny2 = 1e-12f * h * h;
  tbb::parallel_for(tbb::blocked_range<size_t>(0, particles.size(), 512), [&](const tbb::blocked_range<size_t>& range) {
    for (size_t i = range.begin(); i != range.end(); ++i) {
      const float xi = x[i], yi = y[i], zi = z[i];
      const float vxi = vx[i], vyi = vy[i], vzi = vz[i];
      const float pi = p[i];
      const float rhoI = rho[i];
      const float piOverRho2 = pi / (rhoI * rhoI);
      float fpx = 0, fpy = 0, fpz = 0;  // pressure force density / (45 / (pi h^6))
      float fvx = 0, fvy = 0, fvz = 0;  // viscosity force density / (mu 45 / (pi h^6))
      for (const uint32_t* it = neighbors.begin(i); it != neighbors.end(i); ++it) {
        const uint32_t j = *it;
        // r_vec = r_i - r_j
        const float dx = xi - x[j], dy = yi - y[j], dz = zi - z[j];
        const float r2 = dx * dx + dy * dy + dz * dz;
        const float mOverRho = m[j] / rho[j];
        float ux, uy, uz, dist;
        if (r2 > tiny2) {
          dist = std::sqrt(r2);
          const float inv = 1.0f / dist;
          ux = dx * inv; uy = dy * inv; uz = dz * inv;
        } else {  // coincident particles: separate them along x, ordered by id
          dist = 0.0f;
          ux = id[i] < id[j] ? -1.0f : 1.0f; uy = 0.0f; uz = 0.0f;
        }
        const float t = h - dist;
        float press;
        if constexpr (Form == PressureForce::Mueller2003)
          // (5): -m_j (p_i + p_j) / (2 rho_j) * (-45/(pi h^6)) (h - r)^2 r_hat
          press = 0.5f * mOverRho * (pi + p[j]) * t * t;
        else  // rho_i m_j (p_i / rho_i^2 + p_j / rho_j^2) (h - r)^2
          press = rhoI * m[j] * (piOverRho2 + p[j] / (rho[j] * rho[j])) * t * t;
        fpx += press * ux; fpy += press * uy; fpz += press * uz;
        // (6): mu m_j (v_j - v_i) / rho_j * 45/(pi h^6) (h - r)
        const float visc = mOverRho * t;
        fvx += visc * (vx[j] - vxi); fvy += visc * (vy[j] - vyi); fvz += visc * (vz[j] - vzi);
      }
      float wx = 0, wy = 0, wz = 0;  // wall pressure force density
      if (walls.weights) {
        // Virtual wall particles: rest density rho0, the pressure of particle i (mirror).
        const WallContribution c = boxWallContribution(*walls.weights, walls.box, h, xi, yi, zi);
        float factor;
        if constexpr (Form == PressureForce::Mueller2003) factor = pi / walls.restDensity;
        else factor = rhoI * (piOverRho2 + pi / (walls.restDensity * walls.restDensity));
        wx = factor * c.gradient.x(); wy = factor * c.gradient.y(); wz = factor * c.gradient.z();
      }
      const float invRho = 1.0f / rhoI;
      ax[i] = (gradC * fpx + wx + lapC * fvx) * invRho + gravity.x();
      ay[i] = (gradC * fpy + wy + lapC * fvy) * invRho + gravity.y();
      az[i] = (gradC * fpz + wz + lapC * fvz) * invRho + gravity.z();
    }
  });
}

}  // namespace

void computeFluidAcceleration(const NeighborLists& neighbors, ParticleSet& particles, const SpikyKernel& spiky,
                              const ViscosityKernel& viscosity, float dynamicViscosity,
                              const Eigen::Vector3f& gravity, PressureForce form, const WallSums& walls) {
  if (form == PressureForce::Mueller2003)
    accelerate<PressureForce::Mueller2003>(neighbors, particles, spiky, viscosity, dynamicViscosity, gravity, walls);
  else
    accelerate<PressureForce::Monaghan1992>(neighbors, particles, spiky, viscosity, dynamicViscosity, gravity, walls);
}

float calibratedParticleMass(float spacing, float supportRadius, float restDensity) {
  const Poly6Kernel poly6(supportRadius);
  const int reach = static_cast<int>(std::ceil(supportRadius / spacing));
  double sum = 0.0;
  for (int k = -reach; k <= reach; ++k)
    for (int j = -reach; j <= reach; ++j)
      for (int i = -reach; i <= reach; ++i) {
        const double r2 = double(spacing) * spacing * (i * i + j * j + k * k);
        sum += poly6.fromSquared(float(r2));
      }
  return float(restDensity / sum);
}

}  // namespace kurage::sim
