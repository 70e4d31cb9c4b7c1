// The environment lookup; see lights.h. Sun and area light sampling live in the integrators
// (integrators/), which need the scene for shadow rays.
#include "render/lights.h"

#include "render/sampling.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace kurage::render {

namespace {
constexpr float kPi = std::numbers::pi_v<float>;
float luminance(const Eigen::Vector3f& c) { return 0.2126f * c.x() + 0.7152f * c.y() + 0.0722f * c.z(); }
}  // namespace

Eigen::Vector3f environmentRadiance(const Environment& e, const Eigen::Vector3f& direction) {
  switch (e.type) {
    case EnvironmentType::Uniform:
      return e.zenith;
    case EnvironmentType::Gradient: {
      const float t = std::clamp(direction.dot(e.up.normalized()), 0.0f, 1.0f);  // sin(elevation)
      return (1.0f - t) * e.horizon + t * e.zenith;
    }
    case EnvironmentType::Image: {
      if (!e.image || e.image->width() == 0) return Eigen::Vector3f::Zero();
      const Eigen::Vector3f up = e.up.normalized();
      Eigen::Vector3f tangent, bitangent;
      orthonormalBasis(up, tangent, bitangent);
      const float z = std::clamp(direction.dot(up), -1.0f, 1.0f);
      const float phi = std::atan2(direction.dot(bitangent), direction.dot(tangent)) -
                        e.rotationDegrees * std::numbers::pi_v<float> / 180.0f;
      float u = 0.5f + phi / (2.0f * std::numbers::pi_v<float>);
      u -= std::floor(u);
      const float v = std::acos(z) / std::numbers::pi_v<float>;
      const int x = std::clamp(static_cast<int>(u * static_cast<float>(e.image->width())), 0, e.image->width() - 1);
      const int y = std::clamp(static_cast<int>(v * static_cast<float>(e.image->height())), 0, e.image->height() - 1);
      return e.intensity * e.image->at(x, y).head<3>();
    }
  }
  return Eigen::Vector3f::Zero();
}

}  // namespace kurage::render

namespace kurage::render {

// The equirectangular parametrisation of environmentRadiance: theta = pi v from `up`, azimuth
// 2 pi (u - 1/2) + rotation from the tangent towards the bitangent.
Eigen::Vector3f EnvironmentSampler::directionAt(float u, float v) const {
  const float theta = kPi * v, phi = 2.0f * kPi * (u - 0.5f) + rotation_;
  const float sinTheta = std::sin(theta);
  return sinTheta * std::cos(phi) * tangent_ + sinTheta * std::sin(phi) * bitangent_ + std::cos(theta) * up_;
}

EnvironmentSampler::EnvironmentSampler(const Environment& e, const Eigen::Vector3f* below) {
  const bool image = e.type == EnvironmentType::Image;
  if (image && (!e.image || e.image->width() == 0)) return;
  up_ = e.up.normalized();
  orthonormalBasis(up_, tangent_, bitangent_);
  rotation_ = image ? e.rotationDegrees * kPi / 180.0f : 0.0f;
  width_ = image ? e.image->width() : 64;
  height_ = image ? e.image->height() : 32;
  weights_.assign(size_t(width_) * size_t(height_), 0.0f);
  rowCdf_.assign(size_t(height_) * size_t(width_ + 1), 0.0);
  marginal_.assign(size_t(height_) + 1, 0.0);
  for (int y = 0; y < height_; ++y) {
    const float v = (float(y) + 0.5f) / float(height_);
    const float sinTheta = std::sin(kPi * v);
    double row = 0.0;
    for (int x = 0; x < width_; ++x) {
      const float u = (float(x) + 0.5f) / float(width_);
      float w = std::max(0.0f, luminance(environmentRadiance(e, directionAt(u, v)))) * sinTheta;
      if (below && w > 0.0f) {  // wholly below the ground's horizon: corners and centre
        float highest = directionAt(u, v).dot(*below);
        for (int cy = 0; cy <= 1; ++cy)
          for (int cx = 0; cx <= 1; ++cx)
            highest = std::max(highest, directionAt(float(x + cx) / float(width_), float(y + cy) / float(height_)).dot(*below));
        if (highest < 0.0f) w = 0.0f;
      }
      weights_[size_t(y) * size_t(width_) + size_t(x)] = w;
      row += w;
      rowCdf_[size_t(y) * size_t(width_ + 1) + size_t(x) + 1] = row;
    }
    marginal_[size_t(y) + 1] = marginal_[size_t(y)] + row;
  }
  total_ = marginal_.back();
  rowGuide_.assign(size_t(height_) * size_t(width_), 0);
  for (int y = 0; y < height_; ++y)
    buildGuide(rowCdf_.data() + size_t(y) * size_t(width_ + 1), width_, rowGuide_.data() + size_t(y) * size_t(width_));
  marginalGuide_.assign(size_t(height_), 0);
  buildGuide(marginal_.data(), height_, marginalGuide_.data());
}

void EnvironmentSampler::buildGuide(const double* cdf, int count, int* guide) {
  // guide[k]: the answer of find() for the target k / count of the total (a lower bound on the
  // answer for any target in bucket k).
  const double total = cdf[count];
  int i = 0;
  for (int k = 0; k < count; ++k) {
    const double target = double(k) / double(count) * total;
    while (i < count - 1 && cdf[i + 1] <= target) ++i;
    guide[k] = i;
  }
}

int EnvironmentSampler::find(const double* cdf, int count, const int* guide, double target) {
  const double total = cdf[count];
  int k = total > 0.0 ? int(target / total * double(count)) : 0;
  k = std::clamp(k, 0, count - 1);
  int i = guide[k];
  if (cdf[i] > target)  // the guide overshot (rounding at a bucket's edge): search
    return int(std::upper_bound(cdf + 1, cdf + count + 1, target) - cdf) - 1;
  while (i < count - 1 && cdf[i + 1] <= target) ++i;
  return i;
}

Eigen::Vector3f EnvironmentSampler::sample(float u1, float u2, float& pdf) const {
  pdf = 0.0f;
  if (empty()) return up_;
  // Row by the marginal, then column within the row; both by inverting the cumulative sums.
  const double targetRow = double(u1) * total_;
  const int y = std::clamp(find(marginal_.data(), height_, marginalGuide_.data(), targetRow), 0, height_ - 1);
  const double rowWeight = marginal_[size_t(y) + 1] - marginal_[size_t(y)];
  if (!(rowWeight > 0.0)) return up_;
  const double dv = std::clamp((targetRow - marginal_[size_t(y)]) / rowWeight, 0.0, 1.0);
  const double* cdf = rowCdf_.data() + size_t(y) * size_t(width_ + 1);
  const double targetColumn = double(u2) * rowWeight;
  const int x = std::clamp(find(cdf, width_, rowGuide_.data() + size_t(y) * size_t(width_), targetColumn), 0, width_ - 1);
  const float w = weights_[size_t(y) * size_t(width_) + size_t(x)];
  if (!(w > 0.0f)) return up_;
  const double du = std::clamp((targetColumn - cdf[x]) / double(w), 0.0, 1.0);
  const float u = (float(x) + float(du)) / float(width_), v = (float(y) + float(dv)) / float(height_);
  const float sinTheta = std::sin(kPi * v);
  if (!(sinTheta > 0.0f)) return up_;
  pdf = float(double(w) / total_ * double(width_) * double(height_)) / (2.0f * kPi * kPi * sinTheta);
  return directionAt(u, v);
}

float EnvironmentSampler::pdf(const Eigen::Vector3f& d) const {
  if (empty()) return 0.0f;
  const float z = std::clamp(d.dot(up_), -1.0f, 1.0f);
  const float sinTheta = std::sqrt(std::max(0.0f, 1.0f - z * z));
  if (!(sinTheta > 0.0f)) return 0.0f;
  float u = 0.5f + (std::atan2(d.dot(bitangent_), d.dot(tangent_)) - rotation_) / (2.0f * kPi);
  u -= std::floor(u);
  const float v = std::acos(z) / kPi;
  const int x = std::clamp(int(u * float(width_)), 0, width_ - 1);
  const int y = std::clamp(int(v * float(height_)), 0, height_ - 1);
  const float w = weights_[size_t(y) * size_t(width_) + size_t(x)];
  return float(double(w) / total_ * double(width_) * double(height_)) / (2.0f * kPi * kPi * sinTheta);
}

}  // namespace kurage::render
