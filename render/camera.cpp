// Perspective thin-lens camera and camera keyframes; see camera.h.
#include "render/camera.h"

#include "render/sampling.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace kurage::render {

namespace {

// Catmull-Rom interpolation between p1 and p2 at s in [0,1] (uniform parameterisation).
template <class T>
T catmullRom(const T& p0, const T& p1, const T& p2, const T& p3, float s) {
  const float s2 = s * s, s3 = s2 * s;
  return 0.5f * ((2.0f * p1) + (-p0 + p2) * s + (2.0f * p0 - 5.0f * p1 + 4.0f * p2 - p3) * s2 +
                 (-p0 + 3.0f * p1 - 3.0f * p2 + p3) * s3);
}

}  // namespace

Camera cameraAt(const Camera& base, const std::vector<CameraKey>& keys, double time) {
  Camera camera = base;
  if (keys.empty()) return camera;
  const auto apply = [&camera](const CameraKey& k) {
    camera.position = k.position;
    camera.lookAt = k.lookAt;
    camera.verticalFovDegrees = k.verticalFovDegrees;
  };
  if (time <= keys.front().time) { apply(keys.front()); return camera; }
  if (time >= keys.back().time) { apply(keys.back()); return camera; }
  size_t i = 0;
  while (i + 2 < keys.size() && keys[i + 1].time <= time) ++i;
  const CameraKey& k1 = keys[i];
  const CameraKey& k2 = keys[i + 1];
  const CameraKey& k0 = i > 0 ? keys[i - 1] : k1;
  const CameraKey& k3 = i + 2 < keys.size() ? keys[i + 2] : k2;
  const double span = k2.time - k1.time;
  const float s = span > 0.0 ? static_cast<float>((time - k1.time) / span) : 1.0f;
  camera.position = catmullRom(k0.position, k1.position, k2.position, k3.position, s);
  camera.lookAt = catmullRom(k0.lookAt, k1.lookAt, k2.lookAt, k3.lookAt, s);
  camera.verticalFovDegrees = std::clamp(
      catmullRom(k0.verticalFovDegrees, k1.verticalFovDegrees, k2.verticalFovDegrees, k3.verticalFovDegrees, s),
      std::min(k1.verticalFovDegrees, k2.verticalFovDegrees), std::max(k1.verticalFovDegrees, k2.verticalFovDegrees));
  return camera;
}

CameraRays::CameraRays(const Camera& camera, int width, int height) : width_(width), height_(height) {
  if (width <= 0 || height <= 0) throw std::invalid_argument("camera: image size must be positive");
  if (!(camera.verticalFovDegrees > 0.0f && camera.verticalFovDegrees < 180.0f))
    throw std::invalid_argument("camera: vertical field of view must be in (0, 180) degrees");
  if (!(camera.apertureRadius >= 0.0f) || !(camera.focusDistance >= 0.0f))
    throw std::invalid_argument("camera: aperture and focus distance must be >= 0");
  const Eigen::Vector3f view = camera.lookAt - camera.position;
  forward_ = view.normalized();
  right_ = forward_.cross(camera.up).normalized();
  if (view.squaredNorm() == 0.0f || camera.up.squaredNorm() == 0.0f || !right_.allFinite())
    throw std::invalid_argument("camera: position, lookAt and up are degenerate");
  up_ = right_.cross(forward_);
  position_ = camera.position;
  tanHalfFov_ = std::tan(0.5f * camera.verticalFovDegrees * std::numbers::pi_v<float> / 180.0f);
  aspect_ = static_cast<float>(width) / static_cast<float>(height);
  aperture_ = camera.apertureRadius;
  focus_ = camera.focusDistance > 0.0f ? camera.focusDistance : view.norm();
}

Eigen::Vector3f CameraRays::project(const Eigen::Vector3f& world) const {
  const Eigen::Vector3f rel = world - position_;
  const float z = rel.dot(forward_);
  const float px = rel.dot(right_) / z / (aspect_ * tanHalfFov_);  // [-1, 1] across the image
  const float py = rel.dot(up_) / z / tanHalfFov_;
  return {0.5f * (px + 1.0f) * float(width_), 0.5f * (1.0f - py) * float(height_), z};
}

void CameraRays::generate(float x, float y, float u1, float u2, Eigen::Vector3f& origin,
                          Eigen::Vector3f& direction) const {
  // Image plane at distance 1: x in [-aspect, aspect] * tan, y in [-1, 1] * tan, row 0 on top.
  const float px = (2.0f * x / static_cast<float>(width_) - 1.0f) * aspect_ * tanHalfFov_;
  const float py = (1.0f - 2.0f * y / static_cast<float>(height_)) * tanHalfFov_;
  const Eigen::Vector3f d = forward_ + px * right_ + py * up_;
  if (aperture_ == 0.0f) {
    origin = position_;
    direction = d.normalized();
    return;
  }
  const Eigen::Vector3f focusPoint = position_ + focus_ * d;  // d has unit forward component
  const Eigen::Vector2f lens = aperture_ * sampleConcentricDisk(u1, u2);
  origin = position_ + lens.x() * right_ + lens.y() * up_;
  direction = (focusPoint - origin).normalized();
}

}  // namespace kurage::render
