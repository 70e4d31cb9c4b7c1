// What the renderer draws (render/renderer.h): triangle meshes (the level set surfaces, the tank),
// sphere sets (particles shown as spheres) and tubes along curves (the jellyfish's oral arms), each
// with a material (materials.h), over an analytic infinite checker ground, lit by a sun, area lights
// and the environment (lights.h), seen through a perspective camera (camera.h), optionally cut by a
// clip plane.
//
// Units are metres in world space. The ground is the plane through `point` with normal `normal`
// (analytic, truly infinite, receives shadows but casts none). A clip plane removes the meshes,
// spheres and tubes (not the ground) on the side its normal points to, for cross-section views.
//
// Static and moving geometry: `staticMeshes` are meshes that do not move from frame to frame (the
// tank). A Renderer builds their acceleration structure once and keeps it while the next frame's
// static meshes are equal to them, value for value (positions, normals, triangles, material, id);
// any difference rebuilds it. `meshes`, `spheres` and `curves` are rebuilt every frame. Which list a
// mesh is in changes no pixel, only what a frame costs.
#pragma once

#include "render/camera.h"
#include "render/frame_layers.h"
#include "render/lights.h"
#include "render/materials.h"
#include "render/mesh.h"

#include <Eigen/Core>

#include <cstdint>
#include <memory>
#include <vector>

namespace kurage::render {

struct Ground {
  bool enabled = true;
  Eigen::Vector3f point{0, 0, 0};
  Eigen::Vector3f normal{0, 0, 1};
  Eigen::Vector3f albedoA{0.65f, 0.65f, 0.62f};  // diffuse checker colours
  Eigen::Vector3f albedoB{0.3f, 0.3f, 0.28f};
  float checkerSize = 1.0f;  // metres; <= 0 gives a plain albedoA ground
};

struct ClipPlane {
  bool enabled = false;
  Eigen::Vector3f point{0, 0, 0};
  Eigen::Vector3f normal{0, 1, 0};  // geometry where (x - point) . normal > 0 is removed
};

struct SceneObject {
  const TriangleMesh* mesh = nullptr;  // not owned; must outlive the render call
  Material material;
  uint32_t objectId = kObjectFirst;  // FrameLayers::objectId where it is seen first
};

// Spheres of one radius; each may have its own colour (replacing material.albedo).
struct SphereSet {
  std::vector<Eigen::Vector3f> centres;  // metres
  std::vector<Eigen::Vector3f> colours;  // empty, or one per centre
  float radius = 0.5f;                   // metres
  Material material;
  uint32_t objectId = kObjectFirst;
};

// Closed tubes of varying radius along uniform cubic B-splines, traced directly as Embree's
// round B-spline curves (RTC_GEOMETRY_TYPE_ROUND_BSPLINE_CURVE: a circle of the interpolated
// radius swept along the curve, perpendicular to it), never meshed.
//
// A tube's `points` are the B-spline's control points and `radii` its radius at each (metres,
// > 0). A uniform cubic B-spline passes through none of its control points, so the renderer adds
// one more at each end, mirrored through the end point (2 p0 - p1, and likewise the radius):
// the curve then starts exactly at the first point with radius radii.front() and tangent p1 - p0,
// and ends exactly at the last one; n >= 2 points give n - 1 curve segments (a single point
// gives nothing). Embree's tube is open at its ends; the renderer closes each end with the half
// of a sphere of the end radius that lies outside the tube, so the tube is a closed surface and
// dielectric and translucent materials work inside it. The interpolated radius stays > 0 (all
// radii > 0). Limits (Embree's): the radius must stay below the curve's radius of curvature, and
// consecutive points must differ; otherwise the surface shows artefacts.
struct Tube {
  std::vector<Eigen::Vector3f> points;  // metres
  std::vector<float> radii;             // metres, one per point
  uint32_t objectId = 0;                // FrameLayers::objectId; 0: the set's
};

struct CurveSet {
  std::vector<Tube> tubes;
  Material material;
  uint32_t objectId = kObjectFirst;
};

struct RenderScene {
  std::vector<SceneObject> staticMeshes;  // meshes that do not move (see the top of this file)
  std::vector<SceneObject> meshes;
  std::vector<std::shared_ptr<const TriangleMesh>> ownedMeshes;  // keeps meshes built with the scene alive
  std::vector<SphereSet> spheres;
  std::vector<CurveSet> curves;
  Camera camera;
  SunLight sun;
  std::vector<RectLight> rectLights;
  Environment environment;
  Ground ground;
  ClipPlane clip;
};

}  // namespace kurage::render
