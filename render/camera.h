// The camera: perspective projection with a vertical field of view and a look-at frame, an
// optional thin lens for depth of field, and keyframes interpolated over time.
//
// World units are metres. Image coordinates: (0, 0) is the top-left corner of the picture, x to
// the right and y downwards, in pixels. A pinhole (aperture 0) puts everything in focus; a thin
// lens of radius `apertureRadius` focuses the plane at `focusDistance` along the viewing
// direction (0 = the distance to lookAt).
#pragma once

#include <Eigen/Core>

#include <vector>

namespace kurage::render {

struct Camera {
  Eigen::Vector3f position{0, -10, 5};
  Eigen::Vector3f lookAt{0, 0, 0};
  Eigen::Vector3f up{0, 0, 1};
  float verticalFovDegrees = 45.0f;
  float apertureRadius = 0.0f;  // metres; 0 = pinhole
  float focusDistance = 0.0f;   // metres along the view direction; 0 = |lookAt - position|
};

// A camera pose at a time. Between keys, position, look-at point and field of view are
// interpolated with a Catmull-Rom spline through the keys (C1, passes through every key); before
// the first key and after the last the camera holds still.
struct CameraKey {
  double time = 0.0;  // seconds of simulated time
  Eigen::Vector3f position{0, -10, 5};
  Eigen::Vector3f lookAt{0, 0, 0};
  float verticalFovDegrees = 45.0f;
};

// `base` with position, lookAt and field of view taken from the keys at `time` (keys sorted by
// time; an empty list returns `base` unchanged). Up, aperture and focus come from `base`.
Camera cameraAt(const Camera& base, const std::vector<CameraKey>& keys, double time);

// A camera ready to generate rays for an image of the given size.
class CameraRays {
public:
  // Throws std::invalid_argument for a degenerate camera (zero view direction, up parallel to
  // it, field of view outside (0, 180) degrees, negative aperture).
  CameraRays(const Camera& camera, int width, int height);

  // Ray through image point (x, y) in pixels; lens sample (u1, u2) in [0,1)^2 is used only when
  // the aperture is non-zero. `direction` is unit length.
  void generate(float x, float y, float u1, float u2, Eigen::Vector3f& origin, Eigen::Vector3f& direction) const;

  // Where a world point lands: pixel coordinates (x right, y down, as generate() takes them) and,
  // in z, its distance along the viewing direction (<= 0: behind the camera). Pinhole projection.
  Eigen::Vector3f project(const Eigen::Vector3f& world) const;

  const Eigen::Vector3f& position() const { return position_; }
  const Eigen::Vector3f& forward() const { return forward_; }
  const Eigen::Vector3f& right() const { return right_; }
  const Eigen::Vector3f& up() const { return up_; }
  float tanHalfFov() const { return tanHalfFov_; }
  float aspect() const { return aspect_; }

private:
  Eigen::Vector3f position_, forward_, right_, up_;
  float tanHalfFov_ = 1.0f, aspect_ = 1.0f, aperture_ = 0.0f, focus_ = 1.0f;
  int width_ = 1, height_ = 1;
};

}  // namespace kurage::render
