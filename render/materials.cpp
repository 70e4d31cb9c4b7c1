// Material scattering; see materials.h.
//
// Refraction carries weight 1 and omits pbrt's 1/eta^2 radiance scaling: the factor for
// entering a medium cancels the one for leaving it, and every path that reaches a light from a
// camera in air crosses each closed surface an even number of times.
#include "render/materials.h"

#include "render/sampling.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace kurage::render {

using Eigen::Vector3f;

namespace {

constexpr float kInvPi = 1.0f / std::numbers::pi_v<float>;

// The shading normal and the geometric normal, both turned to the side of wo; the shading
// normal is replaced by the geometric one when it faces away from wo.
struct Frame {
  Vector3f n, g;
  float cosO;
  bool outside;  // wo is on the side ng points to (the air, for a dielectric)
};

Frame facingFrame(const Vector3f& wo, const Vector3f& ns, const Vector3f& ng) {
  Frame f;
  f.outside = wo.dot(ng) >= 0.0f;
  f.g = f.outside ? ng : Vector3f(-ng);
  f.n = f.outside ? ns : Vector3f(-ns);
  f.cosO = wo.dot(f.n);
  if (!(f.cosO > 1e-6f)) {
    f.n = f.g;
    f.cosO = std::max(wo.dot(f.g), 1e-6f);
  }
  return f;
}

Vector3f reflect(const Vector3f& wo, const Vector3f& n) { return 2.0f * wo.dot(n) * n - wo; }

// Smooth Fresnel interface: reflect with probability F, else refract (dielectric) or scatter
// diffusely into the other side (translucent).
bool sampleInterface(const Material& m, const Vector3f& albedo, const Vector3f& wo, const Frame& f, float u1,
                     float u2, float u3, ScatterSample& s) {
  const float etaI = f.outside ? 1.0f : m.ior;
  const float etaT = f.outside ? m.ior : 1.0f;
  const float fresnel = fresnelDielectric(f.cosO, etaI, etaT);
  if (u1 < fresnel) {
    s.direction = reflect(wo, f.n);
    if (s.direction.dot(f.g) <= 0.0f) s.direction = reflect(wo, f.g);
    s.weight = Vector3f::Ones();
    s.specular = true;
    s.transmitted = false;
    return true;
  }
  s.transmitted = true;
  if (m.type == MaterialType::Translucent) {
    s.direction = sampleCosineHemisphere(-f.n, u2, u3);
    s.weight = albedo;
    s.specular = false;
    return s.direction.dot(f.g) < 0.0f;
  }
  const auto refract = [&](const Vector3f& n, float cosI, Vector3f& out) {
    const float eta = etaI / etaT;
    const float sin2T = eta * eta * std::max(0.0f, 1.0f - cosI * cosI);
    if (sin2T >= 1.0f) return false;
    out = (-eta * wo + (eta * cosI - std::sqrt(1.0f - sin2T)) * n).normalized();
    return true;
  };
  Vector3f wi;
  if (!refract(f.n, f.cosO, wi) || wi.dot(f.g) >= 0.0f) {
    if (!refract(f.g, std::max(wo.dot(f.g), 1e-6f), wi)) {  // TIR only by the shading normal: reflect
      s.direction = reflect(wo, f.g);
      s.weight = Vector3f::Ones();
      s.specular = true;
      s.transmitted = false;
      return true;
    }
  }
  s.direction = wi;
  s.weight = Vector3f::Ones();
  s.specular = true;
  return true;
}

}  // namespace

Vector3f checkerAlbedo(const Material& m, const Vector3f& albedo, const Vector3f& p) {
  if (!(m.checkerSize > 0.0f)) return albedo;
  const double cells = std::floor(p.x() / m.checkerSize) + std::floor(p.y() / m.checkerSize) + std::floor(p.z() / m.checkerSize);
  return std::fmod(std::abs(cells), 2.0) == 0.0 ? albedo : m.albedoB;
}

double checkerWaveMean(double x0, double x1) {
  // the measure of {s < x : floor(s) odd} relative to s = 0, continuous and piecewise linear
  const auto odd = [](double x) {
    const double pairs = std::floor(0.5 * x);
    return pairs + std::max(x - 2.0 * pairs - 1.0, 0.0);
  };
  if (!(x1 - x0 > 1e-9)) return std::fmod(std::abs(std::floor(x0)), 2.0) == 0.0 ? 1.0 : -1.0;
  return 1.0 - 2.0 * (odd(x1) - odd(x0)) / (x1 - x0);
}

Vector3f checkerBlend(double parity, const Vector3f& a, const Vector3f& b) {
  const float even = float(0.5 * (1.0 + parity));
  return even * a + (1.0f - even) * b;
}

Vector3f checkerAlbedoFiltered(const Material& m, const Vector3f& albedo, const Vector3f& p, const Vector3f& width) {
  if (!(m.checkerSize > 0.0f)) return albedo;
  double parity = 1.0;
  for (int axis = 0; axis < 3; ++axis) {
    const double centre = double(p[axis]) / m.checkerSize, half = 0.5 * double(width[axis]) / m.checkerSize;
    parity *= checkerWaveMean(centre - half, centre + half);
  }
  return checkerBlend(parity, albedo, m.albedoB);
}

float fresnelDielectric(float cosI, float etaI, float etaT) {
  cosI = std::clamp(cosI, 0.0f, 1.0f);
  const float sinT = etaI / etaT * std::sqrt(std::max(0.0f, 1.0f - cosI * cosI));
  if (sinT >= 1.0f) return 1.0f;
  const float cosT = std::sqrt(std::max(0.0f, 1.0f - sinT * sinT));
  const float parallel = (etaT * cosI - etaI * cosT) / (etaT * cosI + etaI * cosT);
  const float perpendicular = (etaI * cosI - etaT * cosT) / (etaI * cosI + etaT * cosT);
  return 0.5f * (parallel * parallel + perpendicular * perpendicular);
}

Vector3f evaluateDiffuseLobe(const Material& m, const Vector3f& albedo, const Vector3f& wo, const Vector3f& wi,
                             const Vector3f& ns, const Vector3f& ng) {
  const Frame f = facingFrame(wo, ns, ng);
  if (m.type == MaterialType::Diffuse) {
    if (wi.dot(f.g) <= 0.0f) return Vector3f::Zero();
    return albedo * (kInvPi * std::max(0.0f, wi.dot(f.n)));
  }
  if (m.type == MaterialType::Translucent) {
    if (wi.dot(f.g) >= 0.0f) return Vector3f::Zero();
    const float etaI = f.outside ? 1.0f : m.ior;
    const float etaT = f.outside ? m.ior : 1.0f;
    const float transmitted = 1.0f - fresnelDielectric(f.cosO, etaI, etaT);
    return albedo * (transmitted * kInvPi * std::max(0.0f, -wi.dot(f.n)));
  }
  return Vector3f::Zero();
}

float diffuseLobePdf(const Material& m, const Vector3f& wo, const Vector3f& wi, const Vector3f& ns,
                     const Vector3f& ng) {
  const Frame f = facingFrame(wo, ns, ng);
  if (m.type == MaterialType::Diffuse) return wi.dot(f.g) > 0.0f ? kInvPi * std::max(0.0f, wi.dot(f.n)) : 0.0f;
  if (m.type == MaterialType::Translucent) {
    if (wi.dot(f.g) >= 0.0f) return 0.0f;
    const float etaI = f.outside ? 1.0f : m.ior;
    const float etaT = f.outside ? m.ior : 1.0f;
    return (1.0f - fresnelDielectric(f.cosO, etaI, etaT)) * kInvPi * std::max(0.0f, -wi.dot(f.n));
  }
  return 0.0f;
}

bool sampleMaterial(const Material& m, const Vector3f& albedo, const Vector3f& wo, const Vector3f& ns,
                    const Vector3f& ng, float u1, float u2, float u3, ScatterSample& s) {
  const Frame f = facingFrame(wo, ns, ng);
  switch (m.type) {
    case MaterialType::Diffuse:
      s.direction = sampleCosineHemisphere(f.n, u1, u2);
      s.weight = albedo;
      s.specular = false;
      s.transmitted = false;
      return s.direction.dot(f.g) > 0.0f;
    case MaterialType::Mirror:
      s.direction = reflect(wo, f.n);
      if (s.direction.dot(f.g) <= 0.0f) s.direction = reflect(wo, f.g);
      s.weight = albedo;
      s.specular = true;
      s.transmitted = false;
      return true;
    case MaterialType::Dielectric:
    case MaterialType::Translucent:
      return sampleInterface(m, albedo, wo, f, u1, u2, u3, s);
  }
  return false;
}

}  // namespace kurage::render
