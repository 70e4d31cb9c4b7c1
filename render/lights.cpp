// The environment lookup; see lights.h. Sun and area light sampling live in the integrator
// (tracer.cpp), which needs the scene for shadow rays.
#include "render/lights.h"

#include "render/sampling.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace kurage::render {

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
