// Deterministic per-pixel random numbers and the warps that turn them into directions.
//
// There is no global random state: every number the renderer draws is a pure function of
// (pixel, sample index, dimension, seed), hashed with a PCG output permutation. An image
// therefore depends only on the scene, the sample count and the seed, never on the thread
// count or the order in which tiles are rendered. The first two dimensions of a camera sample
// (the position inside the pixel) are stratified with a Cranley-Patterson-rotated Hammersley
// set, so that anti-aliasing converges faster than with independent samples.
//
// Directions are unit vectors; pdfs are per unit solid angle.
#pragma once

#include <Eigen/Core>

#include <cmath>
#include <cstdint>
#include <numbers>

namespace kurage::render {

// PCG-RXS-M-XS 32-bit output permutation of a 32-bit state (O'Neill 2014): a bijective hash
// with good avalanche, used as a stateless random function.
inline uint32_t pcgHash(uint32_t v) {
  const uint32_t state = v * 747796405u + 2891336453u;
  const uint32_t word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
  return (word >> 22u) ^ word;
}

// Uniform float in [0, 1) from 24 random bits.
inline float toUnitFloat(uint32_t bits) { return static_cast<float>(bits >> 8u) * 0x1p-24f; }

// The random numbers of one camera sample of one pixel: next() returns dimension 0, 1, 2, ...
class PixelSampler {
public:
  PixelSampler(uint32_t pixelIndex, uint32_t sampleIndex, uint32_t seed)
      : key_(pcgHash(pcgHash(pixelIndex ^ pcgHash(seed)) + sampleIndex)) {}
  float next() { return toUnitFloat(pcgHash(key_ + pcgHash(dimension_++ * 0x9E3779B9u))); }
  uint32_t dimension() const { return dimension_; }

private:
  uint32_t key_;
  uint32_t dimension_ = 0;
};

// Van der Corput radical inverse in base 2.
inline float radicalInverse2(uint32_t bits) {
  bits = (bits << 16u) | (bits >> 16u);
  bits = ((bits & 0x55555555u) << 1u) | ((bits & 0xAAAAAAAAu) >> 1u);
  bits = ((bits & 0x33333333u) << 2u) | ((bits & 0xCCCCCCCCu) >> 2u);
  bits = ((bits & 0x0F0F0F0Fu) << 4u) | ((bits & 0xF0F0F0F0u) >> 4u);
  bits = ((bits & 0x00FF00FFu) << 8u) | ((bits & 0xFF00FF00u) >> 8u);
  return static_cast<float>(bits) * 0x1p-32f;
}

// Sub-pixel position of sample s of n in [0,1)^2: Hammersley point rotated (toroidally) by a
// per-pixel random offset, so neighbouring pixels do not share a pattern.
inline Eigen::Vector2f pixelSamplePosition(uint32_t s, uint32_t n, uint32_t pixelIndex, uint32_t seed) {
  const uint32_t h = pcgHash(pixelIndex * 2654435761u ^ pcgHash(seed + 0x51ED270Bu));
  const float ox = toUnitFloat(h), oy = toUnitFloat(pcgHash(h));
  float x = (static_cast<float>(s) + 0.5f) / static_cast<float>(n) + ox;
  float y = radicalInverse2(s) + oy;
  x -= std::floor(x);
  y -= std::floor(y);
  return {x, y};
}

// Second dimension of the Sobol' sequence (generator matrix of Pascal's triangle mod 2); with
// radicalInverse2 it forms a (0,2)-sequence, so that every prefix of 2^k points is stratified in
// both dimensions (Kollig & Keller 2002). Used where the sample count is not known in advance
// (adaptive sampling).
inline float sobol2(uint32_t index) {
  uint32_t result = 0;
  for (uint32_t v = 1u << 31u; index != 0; index >>= 1u, v ^= v >> 1u)
    if (index & 1u) result ^= v;
  return static_cast<float>(result) * 0x1p-32f;
}

// Veach's power heuristic (beta = 2) for combining two sampling techniques (Veach & Guibas
// 1995, "Optimally combining sampling techniques for Monte Carlo rendering"): the weight of a
// sample drawn with pdf `a` when the other technique would have drawn it with pdf `b`.
inline float powerHeuristic(float a, float b) {
  const float a2 = a * a, b2 = b * b;
  return a2 + b2 > 0.0f ? a2 / (a2 + b2) : 0.0f;
}

// Sub-pixel position of sample s of an open-ended sequence: the (0,2)-sequence (radicalInverse2,
// sobol2) rotated toroidally per pixel as pixelSamplePosition does, so that the first 2^k
// samples of any pixel are stratified whatever number is finally taken (adaptive sampling).
inline Eigen::Vector2f pixelSamplePositionProgressive(uint32_t s, uint32_t pixelIndex, uint32_t seed) {
  const uint32_t h = pcgHash(pixelIndex * 2654435761u ^ pcgHash(seed + 0x51ED270Bu));
  float x = radicalInverse2(s) + toUnitFloat(h), y = sobol2(s) + toUnitFloat(pcgHash(h));
  x -= std::floor(x);
  y -= std::floor(y);
  return {x, y};
}

// An orthonormal basis (t, b, n) around unit n (Duff et al. 2017, branchless).
inline void orthonormalBasis(const Eigen::Vector3f& n, Eigen::Vector3f& t, Eigen::Vector3f& b) {
  const float sign = std::copysign(1.0f, n.z());
  const float a = -1.0f / (sign + n.z());
  const float c = n.x() * n.y() * a;
  t = {1.0f + sign * n.x() * n.x() * a, sign * c, -sign * n.x()};
  b = {c, sign + n.y() * n.y() * a, -n.y()};
}

// The cosine-weighted direction of (u1, u2) in a frame (t, b, n): (r cos phi, r sin phi, z), r =
// sqrt(u1), phi = 2 pi u2, z = sqrt(1 - u1); what sampleCosineHemisphere turns about n, so that
// fixed points can be warped once.
inline Eigen::Vector3f cosineHemisphereLocal(float u1, float u2) {
  const float r = std::sqrt(u1);
  const float phi = 2.0f * std::numbers::pi_v<float> * u2;
  return {r * std::cos(phi), r * std::sin(phi), std::sqrt(std::max(0.0f, 1.0f - u1))};
}

// A local direction (cosineHemisphereLocal) in the frame (t, b, n) of orthonormalBasis(n, t, b).
inline Eigen::Vector3f fromLocal(const Eigen::Vector3f& local, const Eigen::Vector3f& t, const Eigen::Vector3f& b,
                                 const Eigen::Vector3f& n) {
  return (local.x() * t + local.y() * b + local.z() * n).normalized();
}

// Cosine-weighted direction about unit n; pdf = cos / pi.
inline Eigen::Vector3f sampleCosineHemisphere(const Eigen::Vector3f& n, float u1, float u2) {
  Eigen::Vector3f t, b;
  orthonormalBasis(n, t, b);
  return fromLocal(cosineHemisphereLocal(u1, u2), t, b, n);
}

// Uniform direction inside the cone of half-angle acos(cosMax) about unit axis;
// pdf = 1 / (2 pi (1 - cosMax)).
inline Eigen::Vector3f sampleCone(const Eigen::Vector3f& axis, float cosMax, float u1, float u2) {
  const float cosTheta = 1.0f - u1 * (1.0f - cosMax);
  const float sinTheta = std::sqrt(std::max(0.0f, 1.0f - cosTheta * cosTheta));
  const float phi = 2.0f * std::numbers::pi_v<float> * u2;
  Eigen::Vector3f t, b;
  orthonormalBasis(axis, t, b);
  return (sinTheta * std::cos(phi) * t + sinTheta * std::sin(phi) * b + cosTheta * axis).normalized();
}

// Uniform point on the unit disk (concentric mapping, Shirley & Chiu 1997).
inline Eigen::Vector2f sampleConcentricDisk(float u1, float u2) {
  const float a = 2.0f * u1 - 1.0f, b = 2.0f * u2 - 1.0f;
  if (a == 0.0f && b == 0.0f) return {0.0f, 0.0f};
  constexpr float quarterPi = std::numbers::pi_v<float> / 4.0f;
  if (std::abs(a) > std::abs(b)) return {a * std::cos(quarterPi * b / a), a * std::sin(quarterPi * b / a)};
  return {b * std::sin(quarterPi * a / b), b * std::cos(quarterPi * a / b)};  // angle pi/2 - (pi/4) a/b
}

}  // namespace kurage::render
