// Walls made of boundary particles (Akinci, Ihmsen, Akinci, Solenthaler & Teschner, "Versatile
// rigid-fluid coupling for incompressible SPH", ACM TOG 31(4), 2012), for the box container:
// static samples behind each wall that take part in every particle's density sum and pressure.
//
// A sample b carries the volume V_b; a particle i of rest density rho0_i counts it with the mass
// psi_b = rho0_i V_b (Akinci's psi(rho0) = rho0 V_b with the particle's own rest density, so a
// body particle at a wall sees its own material continued, not the fluid's):
//   rho_i   += rho0_i sum_b V_b W(x_i - x_b)                                   (Akinci eq. 4)
//   a_i     -= rho0_i sum_b V_b (p_i / rho_i^2 + p_b / rho_b^2) grad W(x_i - x_b)  (eq. 10, p_b = p_i)
// and the reaction of that force on the wall is dropped (the container is fixed).
//
// Sampling (ours): the samples continue the fluid's cubic lattice (spacing l, first point half a
// spacing from min, as fluid blocks start) through the walls, edges and corners of the box, in
// every layer within the support radius h of the interior. Akinci's V_b = 1 / sum_k W(x_b - x_k)
// over the wall samples is meant for a single layer; on a full lattice continued behind the wall
// it would overcount the layer next to the fluid (whose support is half empty), so every sample
// gets the volume a particle of the fluid's own lattice has, V = m / rho0 of the calibrated mass:
// a particle on the rest lattice next to a wall then sums exactly rho0 (no crowding at the floor,
// no gap), as deep inside the fluid.
//
// The samples never move, so for each particle only two sums matter: sum_b V_b W and
// sum_b V_b grad W (per step, after the sort); boundaryTerms() computes both.
#pragma once

#include "sim/params.h"

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <vector>

namespace kurage::sim {

class BoundaryParticles {
public:
  // Samples the walls of `box` for a fluid of the given spacing and support radius (metres);
  // `volume` is V_b (m^3). Throws std::invalid_argument when an edge of the box is shorter than
  // the support radius (the walls' supports would overlap across the interior).
  BoundaryParticles(const ContainerParams& box, float spacing, float supportRadius, float volume);

  size_t size() const { return x_.size(); }
  Eigen::Vector3f position(size_t b) const { return {x_[b], y_[b], z_[b]}; }
  float volume() const { return volume_; }

  // sum_b V_b W(|x - x_b|) and sum_b V_b grad_x W(x - x_b) for a point x, with the given density
  // kernel (fromSquared) and gradient kernel (derivative); zero for points farther than h from
  // every wall.
  // `hydrostatic`, when not null, receives sum_b V_b (g . (x_b - x)) grad W(x - x_b) for the
  // gravity g: the extra push of walls whose pressure is extrapolated hydrostatically from the
  // particle's (Adami, Hu & Adams 2012 for a wall at rest: p_b = p_i + rho g . (x_b - x_i)).
  template <class DensityKernelT, class GradientKernelT>
  void sums(const DensityKernelT& w, const GradientKernelT& gradW, float px, float py, float pz, float& volumeSum,
            Eigen::Vector3f& gradientSum, const Eigen::Vector3f* gravity = nullptr,
            Eigen::Vector3f* hydrostatic = nullptr) const {
    volumeSum = 0.0f;
    gradientSum.setZero();
    if (hydrostatic) hydrostatic->setZero();
    if (px - inner_.min.x() >= h_ && inner_.max.x() - px >= h_ && py - inner_.min.y() >= h_ &&
        inner_.max.y() - py >= h_ && pz - inner_.min.z() >= h_ && inner_.max.z() - pz >= h_)
      return;
    const Eigen::Vector3i c = cellOf(px, py, pz);
    float vw = 0.0f, gx = 0.0f, gy = 0.0f, gz = 0.0f, hx = 0.0f, hy = 0.0f, hz = 0.0f;
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy) {
        const int cy = c.y() + dy, cz = c.z() + dz;
        if (cy < 0 || cz < 0 || cy >= dims_.y() || cz >= dims_.z()) continue;
        const int x0 = std::max(c.x() - 1, 0), x1 = std::min(c.x() + 1, dims_.x() - 1);
        const size_t row = (size_t(cz) * dims_.y() + cy) * dims_.x();
        for (uint32_t b = cellStart_[row + x0]; b < cellStart_[row + x1 + 1]; ++b) {
          const float dx = px - x_[b], dy2 = py - y_[b], dz2 = pz - z_[b];
          const float r2 = dx * dx + dy2 * dy2 + dz2 * dz2;
          if (r2 >= h2_) continue;
          vw += w.fromSquared(r2);
          if (r2 > 1e-12f * h2_) {
            const float r = std::sqrt(r2);
            const float s = gradW.derivative(r) / r;
            gx += s * dx; gy += s * dy2; gz += s * dz2;
            if (hydrostatic) {
              const float lift = -(gravity->x() * dx + gravity->y() * dy2 + gravity->z() * dz2);  // g . (x_b - x)
              hx += lift * s * dx; hy += lift * s * dy2; hz += lift * s * dz2;
            }
          }
        }
      }
    volumeSum = volume_ * vw;
    gradientSum = volume_ * Eigen::Vector3f(gx, gy, gz);
    if (hydrostatic) *hydrostatic = volume_ * Eigen::Vector3f(hx, hy, hz);
  }

private:
  Eigen::Vector3i cellOf(float px, float py, float pz) const;

  ContainerParams inner_;
  float h_ = 1.0f, h2_ = 1.0f, volume_ = 1.0f;
  Eigen::Vector3f origin_{0, 0, 0};
  float inverseCell_ = 1.0f;
  Eigen::Vector3i dims_{1, 1, 1};
  std::vector<float> x_, y_, z_;      // sorted by cell, x fastest
  std::vector<uint32_t> cellStart_;   // size cells + 1
};

}  // namespace kurage::sim
