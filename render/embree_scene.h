// The scene's meshes, spheres and tubes (scene.h) in Embree 3 bounding volume hierarchies, and
// the ray queries on them: closest hit and occlusion, past the clip plane.
//
// One scene per frame, one BVH over everything, built at RTC_BUILD_QUALITY_HIGH (SAH with
// spatial splits: slower to build, faster to trace). Its geometries, by ID: first the static
// meshes (RenderScene::staticMeshes), then one triangle geometry per moving mesh, one
// RTC_GEOMETRY_TYPE_SPHERE_POINT geometry per sphere set, and per curve set one
// RTC_GEOMETRY_TYPE_ROUND_BSPLINE_CURVE geometry for the tubes and one sphere geometry for their
// end caps. The static meshes are copied, checked and made Embree geometries once, and those are
// attached to every frame's scene for as long as the frames' static meshes equal the copy, value
// for value; a frame whose static meshes differ (another tank, or a camera moved to the other
// side of a wall, which changes the walls drawn) makes them again. The moving geometry is made
// every frame. Limit: the BVH is rebuilt every frame over the static triangles too, which costs
// little for a tank's few walls; a static mesh of millions of triangles would want a BVH of its
// own, instanced, at the price of a second traversal for every ray that crosses its bounds.
//
// The clip plane is applied by re-tracing past clipped hits (at most 64 along a ray). The half of
// each cap sphere that lies inside its tube is removed by an Embree filter callback instead: that
// half meets the tube's wall tangentially at the tube's end, so stepping past a rejected hit there
// could step past the wall too and let the ray out.
//
// The geometry of a frame references the RenderScene it was built from (its moving meshes, sphere
// sets and curve sets): that scene must outlive the frame's queries. The static copies are owned.
// Queries are thread-safe; update() is not, and must not run during queries.
#pragma once

#include "render/hit.h"
#include "render/scene.h"

#include <Eigen/Core>

#include <limits>
#include <memory>
#include <string>

namespace kurage::render {

// A surface a shadow ray crosses (EmbreeScene::crossings): its distance, material and unit
// geometric normal, outward as EmbreeScene::surface orients it.
struct Crossing {
  float t = 0.0f;
  const Material* material = nullptr;
  Eigen::Vector3f ng = Eigen::Vector3f::Zero();
  unsigned geomID = 0;
};

// A hit in the Embree geometry, as the query returns it.
struct EmbreeHit {
  float t = std::numeric_limits<float>::infinity();
  unsigned geomID = ~0u, primID = 0;
  float u = 0.0f, v = 0.0f;        // Embree's hit coordinates (barycentric; curve parameter)
  Eigen::Vector3f ng = Eigen::Vector3f::Zero();  // Embree's geometric normal, not normalised
};

class EmbreeScene {
public:
  // Creates the Embree device. Throws std::runtime_error if Embree cannot.
  EmbreeScene();
  ~EmbreeScene();
  EmbreeScene(const EmbreeScene&) = delete;
  EmbreeScene& operator=(const EmbreeScene&) = delete;

  // Builds the frame's geometry from `scene`, reusing the static meshes' Embree geometries when
  // they are unchanged. Throws std::invalid_argument for bad geometry or materials (naming "mesh 2",
  // "static mesh 0", "sphere set 1", "curve set 0 tube 3") and std::runtime_error if Embree fails.
  void update(const RenderScene& scene);

  // Closest hit along origin + t direction, t in (tnear, tfar), past clipped hits. False: none.
  bool intersect(const Eigen::Vector3f& origin, const Eigen::Vector3f& direction, float tnear, float tfar,
                 RayCounters& counters, EmbreeHit& out) const;
  // Whether anything blocks the segment origin + t direction, t in (0, tfar).
  bool occluded(const Eigen::Vector3f& origin, const Eigen::Vector3f& direction, float tfar,
                RayCounters& counters) const;
  // Every dielectric surface along origin + t direction, t in (0, tfar), past clipped hits, in one
  // traversal (an occlusion query whose filter records and rejects each dielectric hit, Embree's
  // "all hits" pattern), in no particular order, into out[0 .. capacity). Returns how many, or -1
  // when a surface of another material lies on the segment or there are more than `capacity`. A
  // hit on the same geometry within epsilon() of one recorded counts once (a primitive split
  // across BVH leaves is reported twice; a ray through a shared edge meets both triangles).
  int crossings(const Eigen::Vector3f& origin, const Eigen::Vector3f& direction, float tfar, RayCounters& counters,
                Crossing* out, int capacity) const;
  // The surface point of a hit along the ray it was found on: position, normals (outward),
  // material, albedo, object id.
  Hit surface(const Eigen::Vector3f& origin, const Eigen::Vector3f& direction, const EmbreeHit& hit) const;

  // The ray offset against self-intersection, metres: 1e-4 max(1, largest coordinate magnitude of
  // the camera, the ground's point and the geometry).
  float epsilon() const;
  // Throws std::runtime_error naming `what` if Embree reported an error since the device was made.
  void throwIfError(const char* what) const;
  // How many times the static meshes' geometries were made (for tests).
  int staticBuilds() const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Version string of the Embree library in use (for run.json).
std::string embreeVersion();

}  // namespace kurage::render
