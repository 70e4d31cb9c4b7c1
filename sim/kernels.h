// SPH smoothing kernels of Mueller, Charypar & Gross 2003, "Particle-Based Fluid Simulation
// for Interactive Applications" (SCA 2003), which the paper uses (SPEC §1):
//   poly6     for the density sum (3)
//   spiky     gradient for the pressure force (5)
//   viscosity Laplacian for the viscosity force (6)
// Each kernel is a small value type holding its support radius h (metres) and the powers of h
// it needs; it has no global state. All kernels vanish for r >= h and are normalised so that
// their integral over R^3 is 1.
#pragma once

#include <Eigen/Core>

#include <cmath>
#include <numbers>

namespace kurage::sim {

// W_poly6(r) = 315 / (64 pi h^9) (h^2 - r^2)^3
struct Poly6Kernel {
  float h, h2, coefficient;
  explicit Poly6Kernel(float supportRadius)
      : h(supportRadius), h2(supportRadius * supportRadius),
        coefficient(static_cast<float>(315.0 / (64.0 * std::numbers::pi * std::pow(double(supportRadius), 9)))) {}
  // Takes the squared distance: the density loop never needs a square root.
  float fromSquared(float r2) const {
    if (r2 >= h2) return 0.0f;
    const float t = h2 - r2;
    return coefficient * t * t * t;
  }
  float operator()(float r) const { return fromSquared(r * r); }
};

// W_spiky(r) = 15 / (pi h^6) (h - r)^3;  grad W = -45 / (pi h^6) (h - r)^2 r_vec / r
struct SpikyKernel {
  float h, valueCoefficient, gradientCoefficient;
  explicit SpikyKernel(float supportRadius)
      : h(supportRadius),
        valueCoefficient(static_cast<float>(15.0 / (std::numbers::pi * std::pow(double(supportRadius), 6)))),
        gradientCoefficient(static_cast<float>(45.0 / (std::numbers::pi * std::pow(double(supportRadius), 6)))) {}
  float operator()(float r) const {
    if (r >= h) return 0.0f;
    const float t = h - r;
    return valueCoefficient * t * t * t;
  }
  // dW/dr (negative inside the support): the gradient is derivative(r) * r_vec / r.
  float derivative(float r) const {
    if (r >= h) return 0.0f;
    const float t = h - r;
    return -gradientCoefficient * t * t;
  }
  Eigen::Vector3f gradient(const Eigen::Vector3f& rVec) const {
    const float r = rVec.norm();
    if (r <= 0.0f || r >= h) return Eigen::Vector3f::Zero();
    return derivative(r) / r * rVec;
  }
};

// W_visc(r) = 15 / (2 pi h^3) (-r^3 / (2h^3) + r^2 / h^2 + h / (2r) - 1);
// laplacian W = 45 / (pi h^6) (h - r)
struct ViscosityKernel {
  float h, valueCoefficient, laplacianCoefficient;
  explicit ViscosityKernel(float supportRadius)
      : h(supportRadius),
        valueCoefficient(static_cast<float>(15.0 / (2.0 * std::numbers::pi * std::pow(double(supportRadius), 3)))),
        laplacianCoefficient(static_cast<float>(45.0 / (std::numbers::pi * std::pow(double(supportRadius), 6)))) {}
  float operator()(float r) const {
    if (r >= h || r <= 0.0f) return 0.0f;
    const float q = r / h;
    return valueCoefficient * (-0.5f * q * q * q + q * q + 0.5f / q - 1.0f);
  }
  float laplacian(float r) const { return r >= h ? 0.0f : laplacianCoefficient * (h - r); }
};

}  // namespace kurage::sim

namespace kurage::sim {

// Cubic spline kernel (Monaghan 1992) with support radius h, in the form DFSPH uses (Bender &
// Koschier 2017, and SPlisHSPlasH): with q = r / h and sigma = 8 / (pi h^3),
//   W(q) = sigma (6 q^3 - 6 q^2 + 1)  for q <= 1/2,   sigma 2 (1 - q)^3  for 1/2 < q < 1.
// One kernel for the density sum and its gradient, so that the density's time derivative
// sum_j m_j (v_i - v_j) . grad W_ij is the derivative of the density sum itself: the divergence-
// free solver's factor (Bender & Koschier 2017, eq. 13) holds exactly. Its gradient peaks at
// r = h / 3, well inside the nearest-neighbour distance for h = 2 l (poly6's peaks at h / sqrt 5).
struct CubicSplineKernel {
  float h, h2, sigma, invH;
  explicit CubicSplineKernel(float supportRadius)
      : h(supportRadius), h2(supportRadius * supportRadius),
        sigma(static_cast<float>(8.0 / (std::numbers::pi * std::pow(double(supportRadius), 3)))),
        invH(1.0f / supportRadius) {}
  float operator()(float r) const {
    const float q = r * invH;
    if (q >= 1.0f) return 0.0f;
    if (q <= 0.5f) return sigma * (6.0f * q * q * (q - 1.0f) + 1.0f);
    const float t = 1.0f - q;
    return sigma * 2.0f * t * t * t;
  }
  float fromSquared(float r2) const { return r2 >= h2 ? 0.0f : (*this)(std::sqrt(r2)); }
  // dW/dr (<= 0): the gradient is derivative(r) * r_vec / r.
  float derivative(float r) const {
    const float q = r * invH;
    if (q >= 1.0f) return 0.0f;
    if (q <= 0.5f) return sigma * invH * q * (18.0f * q - 12.0f);
    const float t = 1.0f - q;
    return -6.0f * sigma * invH * t * t;
  }
  Eigen::Vector3f gradient(const Eigen::Vector3f& rVec) const {
    const float r = rVec.norm();
    if (r <= 0.0f || r >= h) return Eigen::Vector3f::Zero();
    return derivative(r) / r * rVec;
  }
};

// The kernel of a solver's density sum (and, for DFSPH, of its pressure gradient).
enum class DensityKernel { Poly6, CubicSpline };

}  // namespace kurage::sim
