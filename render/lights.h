// Lights: a directional sun with an angular size, one-sided rectangular area lights, and the
// environment (sky gradient, uniform, or a latitude-longitude image) seen by rays that leave
// the scene. Radiometric quantities are linear RGB; radiance is W/(m^2 sr) in arbitrary units,
// irradiance W/m^2 in the same units.
//
// The sun and the area lights are sampled by next-event estimation (tracer.cpp); the
// environment is found only by rays that escape (no importance sampling), which is exact for the
// analytic furnace tests and fine for smooth skies.
#pragma once

#include "render/image.h"

#include <Eigen/Core>

#include <memory>

namespace kurage::render {

// The sun: a disk of uniform radiance subtending `angularDiameterDegrees`, specified by the
// irradiance it gives a surface facing it. 0 degrees gives a point (delta) light with hard
// shadows; the real sun is 0.53 degrees.
struct SunLight {
  Eigen::Vector3f direction{-0.4f, -0.3f, -1.0f};  // direction the light travels (need not be unit)
  Eigen::Vector3f irradiance{2.6f, 2.5f, 2.3f};    // on a surface facing the sun
  float angularDiameterDegrees = 0.53f;
};

// A rectangle corner + s edgeU + t edgeV (s, t in [0,1]) emitting `radiance` from the side that
// edgeU x edgeV points to; the back is black. Seen directly and in mirrors; it casts no shadow.
struct RectLight {
  Eigen::Vector3f corner{0, 0, 10};
  Eigen::Vector3f edgeU{2, 0, 0};
  Eigen::Vector3f edgeV{0, 2, 0};
  Eigen::Vector3f radiance{10, 10, 10};
};

enum class EnvironmentType { Gradient, Uniform, Image };

// Radiance arriving from directions that hit nothing.
//   gradient  horizon colour at and below the horizon, blending linearly in sin(elevation) to
//             the zenith colour straight up
//   uniform   `zenith` from every direction (the furnace)
//   image     an equirectangular (latitude-longitude) picture, decoded to linear values, times
//             `intensity`; its centre column looks along +x rotated by `rotationDegrees` about up
struct Environment {
  EnvironmentType type = EnvironmentType::Gradient;
  Eigen::Vector3f zenith{0.35f, 0.55f, 0.9f};
  Eigen::Vector3f horizon{0.85f, 0.9f, 0.95f};
  Eigen::Vector3f up{0, 0, 1};
  std::shared_ptr<const Image> image;  // for EnvironmentType::Image
  float intensity = 1.0f;
  float rotationDegrees = 0.0f;
};

// Radiance of the environment in unit direction `direction`.
Eigen::Vector3f environmentRadiance(const Environment& environment, const Eigen::Vector3f& direction);

}  // namespace kurage::render
