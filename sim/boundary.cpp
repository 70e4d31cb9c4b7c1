#include "sim/boundary.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

namespace kurage::sim {

void enforceBoxWalls(ParticleSet& particles, const ContainerParams& container, float inset) {
  float* pos[3] = {particles.x.data(), particles.y.data(), particles.z.data()};
  float* vel[3] = {particles.vx.data(), particles.vy.data(), particles.vz.data()};
  const bool noSlip = container.walls == WallSlip::NoSlip;
  const Eigen::Vector3f lo = container.min.array() + inset, hi = container.max.array() - inset;
  tbb::parallel_for(tbb::blocked_range<size_t>(0, particles.size(), 4096), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) {
      bool hit = false;
      for (int a = 0; a < 3; ++a) {
        float& p = pos[a][i];
        if (p < lo[a]) {
          p = lo[a];  // back onto the wall, zero distance
          if (vel[a][i] < 0.0f) vel[a][i] = 0.0f;
          hit = true;
        } else if (p > hi[a]) {
          p = hi[a];
          if (vel[a][i] > 0.0f) vel[a][i] = 0.0f;
          hit = true;
        }
      }
      if (hit && noSlip) vel[0][i] = vel[1][i] = vel[2][i] = 0.0f;  // the paper's no-slip
    }
  });
}

}  // namespace kurage::sim

namespace kurage::sim {

WallWeights::WallWeights(float spacing, float supportRadius, float particleMass, DensityKernel kernel)
    : h_(supportRadius) {
  const int samples = 128;
  step_ = h_ / (samples - 1);
  density_.assign(samples, 0.0f);
  gradient_.assign(samples, 0.0f);
  liftNormal_.assign(samples, 0.0f);
  liftTangential_.assign(samples, 0.0f);
  // The fluid's own pair: poly6 and spiky (the paper's), or the cubic spline for both.
  const Poly6Kernel poly6(h_);
  const SpikyKernel spiky(h_);
  const CubicSplineKernel cubic(h_);
  const bool paper = kernel == DensityKernel::Poly6;
  const auto W = [&](double r) { return double(paper ? poly6(float(r)) : cubic(float(r))); };
  const auto dW = [&](double r) { return double(paper ? spiky.derivative(float(r)) : cubic.derivative(float(r))); };
  const int lateral = 8;  // lateral offsets averaged per axis
  const int reach = int(std::ceil(h_ / spacing)) + 1;
  for (int s = 0; s < samples; ++s) {
    const double d = s * step_;
    double rho = 0.0, grad = 0.0, liftN = 0.0, liftT = 0.0;
    for (int oy = 0; oy < lateral; ++oy)
      for (int ox = 0; ox < lateral; ++ox)
        for (int k = 0; k <= reach; ++k)
          for (int j = -reach; j <= reach; ++j)
            for (int i = -reach; i <= reach; ++i) {
              // Particle at (0, 0, d); wall lattice point at lateral offset, depth (k + 1/2) l.
              const double dx = (i + (ox + 0.5) / lateral) * spacing;
              const double dy = (j + (oy + 0.5) / lateral) * spacing;
              const double dz = d + (k + 0.5) * spacing;  // normal separation
              const double r = std::sqrt(dx * dx + dy * dy + dz * dz);
              if (r >= h_) continue;
              const double dw = dW(r);
              rho += W(r);
              grad += -dw * dz / r;  // -dW/dr r_hat . n, r_hat . n = dz / r
              liftN += dw / r * dz * dz;  // A(d), B(d): boundary.h, liftNormal
              liftT += dw / r * 0.5 * (dx * dx + dy * dy);
            }
    const double norm = double(lateral) * lateral;
    density_[size_t(s)] = float(particleMass * rho / norm);
    gradient_[size_t(s)] = float(particleMass * grad / norm);
    liftNormal_[size_t(s)] = float(particleMass * liftN / norm);
    liftTangential_[size_t(s)] = float(particleMass * liftT / norm);
  }
  // Calibration (as for the particle mass): a particle of the initial lattice next to a wall, half
  // a spacing from it, gets exactly the density it would have deep inside the fluid. The lateral
  // average above undercounts that case by about half a percent, which a stiff state equation
  // turns into a large pressure error.
  double aligned = 0.0;
  for (int k = 0; k <= reach; ++k)
    for (int j = -reach; j <= reach; ++j)
      for (int i = -reach; i <= reach; ++i) {
        const double dz = 0.5 * spacing + (k + 0.5) * spacing;
        const double r = std::sqrt(double(i * i + j * j) * spacing * spacing + dz * dz);
        aligned += W(r);
      }
  const double scale = particleMass * aligned / lookup(density_, 0.5f * spacing);
  for (float& v : density_) v = float(v * scale);
  for (float& v : gradient_) v = float(v * scale);
  for (float& v : liftNormal_) v = float(v * scale);
  for (float& v : liftTangential_) v = float(v * scale);

  // Edge table: lattice points behind both walls (depths (i + 1/2) l and (j + 1/2) l), averaged
  // over the offset along the edge, with the same calibration.
  edgeSamples_ = 33;
  edgeStep_ = h_ / (edgeSamples_ - 1);
  edge_.assign(size_t(edgeSamples_) * edgeSamples_, Edge{});
  for (int s1 = 0; s1 < edgeSamples_; ++s1)
    for (int s2 = 0; s2 < edgeSamples_; ++s2) {
      const double d1 = s1 * edgeStep_, d2 = s2 * edgeStep_;
      double rho = 0.0, g1 = 0.0, g2 = 0.0;
      for (int o = 0; o < lateral; ++o)
        for (int i = 0; i <= reach; ++i)
          for (int j = 0; j <= reach; ++j)
            for (int k = -reach; k <= reach; ++k) {
              const double a1 = d1 + (i + 0.5) * spacing, a2 = d2 + (j + 0.5) * spacing;
              const double a3 = (k + (o + 0.5) / lateral) * spacing;
              const double r = std::sqrt(a1 * a1 + a2 * a2 + a3 * a3);
              if (r >= h_) continue;
              rho += W(r);
              const double dw = -dW(r);
              g1 += dw * a1 / r;
              g2 += dw * a2 / r;
            }
      Edge& e = edge_[size_t(s1) * edgeSamples_ + size_t(s2)];
      e.density = float(particleMass * scale * rho / lateral);
      e.gradient1 = float(particleMass * scale * g1 / lateral);
      e.gradient2 = float(particleMass * scale * g2 / lateral);
    }

}

WallWeights::Edge WallWeights::edge(float d1, float d2) const {
  if (d1 >= h_ || d2 >= h_) return {};
  const float u = std::max(d1, 0.0f) / edgeStep_, v = std::max(d2, 0.0f) / edgeStep_;
  const size_t i = std::min(size_t(u), size_t(edgeSamples_ - 2)), j = std::min(size_t(v), size_t(edgeSamples_ - 2));
  const float fu = u - float(i), fv = v - float(j);
  const size_t n = size_t(edgeSamples_);
  const Edge& e00 = edge_[i * n + j];
  const Edge& e10 = edge_[(i + 1) * n + j];
  const Edge& e01 = edge_[i * n + j + 1];
  const Edge& e11 = edge_[(i + 1) * n + j + 1];
  auto mix = [&](float Edge::*field) {
    return (1 - fu) * (1 - fv) * e00.*field + fu * (1 - fv) * e10.*field + (1 - fu) * fv * e01.*field +
           fu * fv * e11.*field;
  };
  return {mix(&Edge::density), mix(&Edge::gradient1), mix(&Edge::gradient2)};
}

float WallWeights::lookup(const std::vector<float>& table, float d) const {
  if (d >= h_) return 0.0f;
  const float u = std::max(d, 0.0f) / step_;
  const size_t i = std::min(size_t(u), table.size() - 2);
  const float f = u - float(i);
  return table[i] * (1.0f - f) + table[i + 1] * f;
}

}  // namespace kurage::sim
