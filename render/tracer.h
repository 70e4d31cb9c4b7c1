// Headless Embree 3 ray tracer for the skeleton pipeline: a pinhole camera, one directional
// light with hard shadows, Lambert shading of triangle meshes over an infinite ground plane,
// and a sky colour for rays that leave the scene. Tiles are rendered in parallel with TBB; the
// image does not depend on the thread count (each pixel's sample positions are fixed).
//
// Units are metres in world space; the up direction is the camera's `up`, the ground plane is
// the plane through `groundPoint` with normal `groundNormal`.
#pragma once

#include "render/image.h"
#include "render/mesh.h"

#include <Eigen/Core>

#include <vector>

namespace kurage::render {

struct Camera {
  Eigen::Vector3f position{0, -10, 5};
  Eigen::Vector3f lookAt{0, 0, 0};
  Eigen::Vector3f up{0, 0, 1};
  float verticalFovDegrees = 45.0f;
};

struct DirectionalLight {
  Eigen::Vector3f direction{-0.4f, -0.3f, -1.0f};  // direction the light travels (need not be unit)
  Eigen::Vector3f radiance{1.1f, 1.05f, 0.95f};      // irradiance on a surface facing the light
};

struct Material {
  Eigen::Vector3f albedo{0.8f, 0.8f, 0.8f};  // Lambert reflectance in [0,1]
};

struct Ground {
  bool enabled = true;
  Eigen::Vector3f point{0, 0, 0};
  Eigen::Vector3f normal{0, 0, 1};
  Eigen::Vector3f albedoA{0.75f, 0.75f, 0.72f};  // checker colours
  Eigen::Vector3f albedoB{0.55f, 0.55f, 0.52f};
  float checkerSize = 1.0f;  // metres; <= 0 gives a plain albedoA ground
};

struct RenderSettings {
  int width = 640;
  int height = 360;
  int samplesPerPixel = 4;  // stratified, fixed positions per pixel
  Eigen::Vector3f skyZenith{0.35f, 0.55f, 0.9f};
  Eigen::Vector3f skyHorizon{0.85f, 0.9f, 0.95f};
  float ambient = 0.35f;  // fraction of the sky colour added as uniform ambient light
};

struct SceneObject {
  const TriangleMesh* mesh = nullptr;  // not owned; must outlive render()
  Material material;
};

// Renders one frame. Throws std::runtime_error if Embree cannot be initialised.
Image renderFrame(const std::vector<SceneObject>& objects, const Camera& camera,
                  const DirectionalLight& light, const Ground& ground, const RenderSettings& settings);

// Version string of the Embree library in use (for run.json).
std::string embreeVersion();

}  // namespace kurage::render
