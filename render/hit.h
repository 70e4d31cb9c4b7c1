// What a ray meets (the integrators' view of a surface point), and the count of rays traced.
//
// Conventions as in materials.h: `ng` is the geometric normal pointing out of the object (up for
// the ground, towards the emitting side for an area light), `ns` the shading normal on the same
// side. Distances are metres along a unit direction.
#pragma once

#include "render/frame_layers.h"
#include "render/materials.h"

#include <Eigen/Core>

#include <cstdint>
#include <limits>

namespace kurage::render {

struct Hit {
  enum Kind { None, Surface, Ground, Light } kind = None;
  float t = std::numeric_limits<float>::infinity();
  Eigen::Vector3f point;
  Eigen::Vector3f ng;
  Eigen::Vector3f ns;
  const Material* material = nullptr;  // null for the ground (a plain Lambert surface) and lights
  Eigen::Vector3f albedo;              // the material's, or its texture's, at `point`
  int light = -1;                      // Light: index into RenderScene::rectLights
  uint32_t objectId = kObjectSky;      // FrameLayers::objectId
};

// Rays counted by one worker (a tile range), added to the frame's totals when it is done.
struct RayCounters {
  uint64_t primary = 0;  // camera rays
  uint64_t total = 0;    // every Embree query
  uint64_t samples = 0;  // camera samples (paths, or Whitted trees)
};

}  // namespace kurage::render
