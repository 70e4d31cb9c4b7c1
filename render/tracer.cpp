// Embree 3 path tracer; see tracer.h.
//
// Per frame: one RTCDevice and RTCScene holding one triangle geometry per mesh, one
// RTC_GEOMETRY_TYPE_SPHERE_POINT geometry per sphere set, and per curve set one
// RTC_GEOMETRY_TYPE_ROUND_BSPLINE_CURVE geometry (the tubes) and one sphere geometry (their end
// caps) (buffers copied into Embree-allocated, correctly padded storage). The ground and the area
// lights are intersected analytically here. The clip plane is applied by re-tracing past clipped
// hits. The half of each cap sphere that lies inside its tube is removed by an Embree filter
// callback instead: that half meets the tube's wall tangentially at the tube's end, so stepping
// past a rejected hit there could step past the wall too and let the ray out. Tiles of 16x16
// pixels are rendered in parallel with TBB.
#include "render/tracer.h"

#include "render/sampling.h"

#include <embree3/rtcore.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <mutex>
#include <numbers>
#include <stdexcept>
#include <string>

namespace kurage::render {
namespace {

using Eigen::Vector2f;
using Eigen::Vector3f;

constexpr float kInfinity = std::numeric_limits<float>::infinity();
constexpr int kTileSize = 16;
constexpr int kMaxClipSkips = 64;  // clipped hits skipped along one ray before giving up
constexpr int kMaxShadowCrossings = 16;  // dielectric surfaces a shadow ray may pass

// The first error Embree reports through the device's error callback (any thread).
struct EmbreeErrors {
  std::mutex mutex;
  std::string first;
};

void onEmbreeError(void* userPtr, RTCError code, const char* message) {
  auto* errors = static_cast<EmbreeErrors*>(userPtr);
  std::lock_guard lock(errors->mutex);
  if (errors->first.empty())
    errors->first = "Embree error " + std::to_string(static_cast<int>(code)) + ": " + (message ? message : "");
}

using DevicePtr = std::unique_ptr<RTCDeviceTy, decltype(&rtcReleaseDevice)>;
using ScenePtr = std::unique_ptr<RTCSceneTy, decltype(&rtcReleaseScene)>;

DevicePtr newDevice() {
  DevicePtr device(rtcNewDevice(nullptr), &rtcReleaseDevice);
  if (!device)
    throw std::runtime_error("Embree: cannot create device (error " +
                             std::to_string(static_cast<int>(rtcGetDeviceError(nullptr))) + ")");
  return device;
}

void throwIfError(RTCDevice device, EmbreeErrors& errors, const char* what) {
  const RTCError code = rtcGetDeviceError(device);
  std::lock_guard lock(errors.mutex);
  if (code != RTC_ERROR_NONE || !errors.first.empty())
    throw std::runtime_error(std::string("Embree: ") + what + " failed: " +
                             (errors.first.empty() ? "error " + std::to_string(static_cast<int>(code)) : errors.first));
}

void checkMaterial(const Material& m, const std::string& name) {
  if (!(m.ior >= 1.0f && m.ior <= 4.0f)) throw std::invalid_argument(name + ": ior must be in [1, 4]");
  if (!(m.absorption.minCoeff() >= 0.0f)) throw std::invalid_argument(name + ": absorption must be >= 0");
  if (!(m.albedo.minCoeff() >= 0.0f && m.albedo.maxCoeff() <= 1.0f && m.albedoB.minCoeff() >= 0.0f &&
        m.albedoB.maxCoeff() <= 1.0f))
    throw std::invalid_argument(name + ": albedo must be in [0, 1]");
}

// Copies one mesh into a committed Embree triangle geometry with the given ID.
void addMesh(RTCDevice device, RTCScene scene, const TriangleMesh& mesh, unsigned geomID, const std::string& name) {
  if (!mesh.normals.empty() && mesh.normals.size() != mesh.positions.size())
    throw std::invalid_argument(name + ": normals must be empty or one per position");
  for (const Eigen::Vector3i& t : mesh.triangles)
    if (t.minCoeff() < 0 || static_cast<size_t>(t.maxCoeff()) >= mesh.positions.size())
      throw std::invalid_argument(name + ": triangle index out of range");
  RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(
      geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), mesh.positions.size()));
  auto* indices = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
      geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), mesh.triangles.size()));
  if (vertices && indices) {
    for (size_t i = 0; i < mesh.positions.size(); ++i)
      for (int k = 0; k < 3; ++k) vertices[3 * i + k] = mesh.positions[i][k];
    for (size_t i = 0; i < mesh.triangles.size(); ++i)
      for (int k = 0; k < 3; ++k) indices[3 * i + k] = static_cast<unsigned>(mesh.triangles[i][k]);
  }
  rtcSetGeometryBuildQuality(geometry, RTC_BUILD_QUALITY_HIGH);
  rtcCommitGeometry(geometry);
  rtcAttachGeometryByID(scene, geometry, geomID);
  rtcReleaseGeometry(geometry);
}

void addSpheres(RTCDevice device, RTCScene scene, const SphereSet& set, unsigned geomID, const std::string& name) {
  if (!(set.radius > 0.0f)) throw std::invalid_argument(name + ": radius must be > 0");
  if (!set.colours.empty() && set.colours.size() != set.centres.size())
    throw std::invalid_argument(name + ": colours must be empty or one per centre");
  RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_SPHERE_POINT);
  auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(
      geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4, 4 * sizeof(float), set.centres.size()));
  if (vertices)
    for (size_t i = 0; i < set.centres.size(); ++i) {
      for (int k = 0; k < 3; ++k) vertices[4 * i + k] = set.centres[i][k];
      vertices[4 * i + 3] = set.radius;
    }
  rtcCommitGeometry(geometry);
  rtcAttachGeometryByID(scene, geometry, geomID);
  rtcReleaseGeometry(geometry);
}

// The control point k = -1 .. n of a tube of n >= 2 points (x, y, z, radius): the points
// themselves and, at k = -1 and k = n, the end points mirrored through the ends (see Tube).
Eigen::Vector4f tubeControlPoint(const Tube& tube, int k) {
  const int n = static_cast<int>(tube.points.size());
  const auto at = [&](int i) {
    Eigen::Vector4f c;
    c << tube.points[size_t(i)], tube.radii[size_t(i)];
    return c;
  };
  if (k < 0) return 2.0f * at(0) - at(1);
  if (k >= n) return 2.0f * at(n - 1) - at(n - 2);
  return at(k);
}

// Uniform cubic B-spline segment with control points c0..c3 at u in [0, 1].
Eigen::Vector4f bspline(const Eigen::Vector4f& c0, const Eigen::Vector4f& c1, const Eigen::Vector4f& c2,
                        const Eigen::Vector4f& c3, float u) {
  const float s = 1.0f - u;
  return (s * s * s * c0 + (3.0f * u * u * u - 6.0f * u * u + 4.0f) * c1 +
          (-3.0f * u * u * u + 3.0f * u * u + 3.0f * u + 1.0f) * c2 + u * u * u * c3) /
         6.0f;
}

// The plane that cuts a tube off at one end: through the end point, normal along the tube (the
// curve's tangent there, p1 - p0 with the mirrored end control point), pointing into the tube.
struct CapPlane {
  Vector3f point;
  Vector3f inward;
};

// Embree filter of the cap spheres (intersect and occluded queries): rejects hits on the half of
// a sphere inside its tube. The hit distance is the ray's tfar during the callback.
void capFilter(const RTCFilterFunctionNArguments* args) {
  const auto* planes = static_cast<const std::vector<CapPlane>*>(args->geometryUserPtr);
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] == 0) continue;
    const float t = RTCRayN_tfar(args->ray, args->N, i);
    const Vector3f p(RTCRayN_org_x(args->ray, args->N, i) + t * RTCRayN_dir_x(args->ray, args->N, i),
                     RTCRayN_org_y(args->ray, args->N, i) + t * RTCRayN_dir_y(args->ray, args->N, i),
                     RTCRayN_org_z(args->ray, args->N, i) + t * RTCRayN_dir_z(args->ray, args->N, i));
    const CapPlane& plane = (*planes)[RTCHitN_primID(args->hit, args->N, i)];
    if ((p - plane.point).dot(plane.inward) > 0.0f) args->valid[i] = 0;
  }
}

// One Embree round B-spline geometry holding every tube of the set with >= 2 points, and one
// sphere geometry holding their end caps (two per tube: start, end), filtered by capFilter with
// `planes` (filled here; must outlive the scene). `segments` and `caps` get, per primitive ID,
// the tube and the segment index (curves) or the end, 0 or 1 (caps).
void addCurves(RTCDevice device, RTCScene scene, const CurveSet& set, unsigned curveID, unsigned capID,
               std::vector<std::pair<uint32_t, uint32_t>>& segments, std::vector<std::pair<uint32_t, uint32_t>>& caps,
               std::vector<CapPlane>& planes) {
  size_t vertexCount = 0;
  for (uint32_t t = 0; t < set.tubes.size(); ++t) {
    const Tube& tube = set.tubes[t];
    if (tube.points.size() < 2) continue;
    vertexCount += tube.points.size() + 2;
    for (uint32_t i = 0; i + 1 < tube.points.size(); ++i) segments.emplace_back(t, i);
    caps.emplace_back(t, 0u);
    caps.emplace_back(t, 1u);
  }
  RTCGeometry curves = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_ROUND_BSPLINE_CURVE);
  auto* vertices = static_cast<float*>(
      rtcSetNewGeometryBuffer(curves, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4, 4 * sizeof(float), vertexCount));
  auto* indices = static_cast<unsigned*>(
      rtcSetNewGeometryBuffer(curves, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT, sizeof(unsigned), segments.size()));
  RTCGeometry spheres = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_SPHERE_POINT);
  auto* centres = static_cast<float*>(
      rtcSetNewGeometryBuffer(spheres, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4, 4 * sizeof(float), caps.size()));
  if (vertices && indices && centres) {
    size_t v = 0, segment = 0, cap = 0;
    for (const Tube& tube : set.tubes) {
      const int n = static_cast<int>(tube.points.size());
      if (n < 2) continue;
      // Segment i uses control points i-1 .. i+2 (vertices first + i .. first + i + 3) and runs
      // from point i to point i+1.
      for (int i = 0; i + 1 < n; ++i) indices[segment++] = static_cast<unsigned>(v + size_t(i));
      for (int k = -1; k <= n; ++k) {
        const Eigen::Vector4f c = tubeControlPoint(tube, k);
        for (int j = 0; j < 4; ++j) vertices[4 * v + size_t(j)] = c[j];
        ++v;
      }
      for (const int end : {0, n - 1}) {
        const Vector3f& tip = tube.points[size_t(end)];
        for (int j = 0; j < 3; ++j) centres[4 * cap + size_t(j)] = tip[j];
        centres[4 * cap + 3] = tube.radii[size_t(end)];
        planes.push_back({tip, tube.points[size_t(end == 0 ? 1 : n - 2)] - tip});
        ++cap;
      }
    }
  }
  rtcSetGeometryUserData(spheres, &planes);
  rtcSetGeometryIntersectFilterFunction(spheres, capFilter);
  rtcSetGeometryOccludedFilterFunction(spheres, capFilter);
  for (const auto& [geometry, id] : {std::pair{curves, curveID}, std::pair{spheres, capID}}) {
    rtcCommitGeometry(geometry);
    rtcAttachGeometryByID(scene, geometry, id);
    rtcReleaseGeometry(geometry);
  }
}

void checkCurves(const CurveSet& set, const std::string& name) {
  for (size_t t = 0; t < set.tubes.size(); ++t) {
    const Tube& tube = set.tubes[t];
    const std::string what = name + " tube " + std::to_string(t);
    if (tube.radii.size() != tube.points.size()) throw std::invalid_argument(what + ": needs one radius per point");
    for (size_t i = 0; i < tube.points.size(); ++i) {
      if (!(tube.radii[i] > 0.0f) || !std::isfinite(tube.radii[i]))
        throw std::invalid_argument(what + ": radii must be > 0 and finite");
      if (!tube.points[i].allFinite()) throw std::invalid_argument(what + ": points must be finite");
    }
  }
}

// What a geometry ID refers to.
struct Geometry {
  const SceneObject* mesh = nullptr;
  const SphereSet* spheres = nullptr;
  const CurveSet* curves = nullptr;  // with `caps` false: the tubes, true: their end caps
  bool caps = false;
  std::vector<std::pair<uint32_t, uint32_t>> primitives;  // curves: (tube, segment); caps: (tube, end 0/1)
  std::unique_ptr<std::vector<CapPlane>> capPlanes;       // caps: capFilter's data, by primitive ID
};

// Everything a worker thread needs; read-only during rendering.
struct Frame {
  RTCScene scene = nullptr;
  const RenderScene* input = nullptr;
  const RenderSettings* settings = nullptr;
  std::vector<Geometry> geometries;  // by geomID
  Vector3f toSun;                    // unit, towards the sun
  float sunCosMax = 1.0f;            // cos of the sun's angular radius
  Vector3f sunRadiance;              // irradiance / solid angle (0 for a point sun)
  bool sunOn = false;
  Vector3f groundNormal;             // unit
  Vector3f groundU, groundV;         // unit, spanning the ground plane (checker axes)
  Vector3f clipNormal;               // unit
  float epsilon = 1e-4f;             // ray offset against self-intersection, metres
  EnvironmentSampler environment;    // empty unless the environment is sampled as a light
  // whitted: the fixed points warped to sky directions, skyDirections x samplesPerPixel of them
  // (one Hammersley set); the pixel's sample s takes points s, s + S, s + 2 S, ... (S = skySamples)
  std::vector<Eigen::Vector2f> skySet;
  int skySamples = 1;
};

// Ray statistics of one tile, added to the frame's totals when the tile is done.
struct Counters {
  uint64_t primary = 0;
  uint64_t total = 0;
  uint64_t samples = 0;
};

struct Hit {
  enum Kind { None, Surface, Ground, Light } kind = None;
  float t = kInfinity;
  Vector3f point;
  Vector3f ng;  // geometric normal, outward (object) or up (ground) or emitting side (light)
  Vector3f ns;  // shading normal, same side as ng
  const Material* material = nullptr;
  Vector3f albedo;
  int light = -1;
  uint32_t objectId = kObjectSky;  // FrameLayers::objectId
};

bool clipped(const Frame& f, const Vector3f& p) {
  return f.input->clip.enabled && (p - f.input->clip.point).dot(f.clipNormal) > 0.0f;
}

// An Embree hit.
struct EmbreeHit {
  float t = kInfinity;
  unsigned geomID = RTC_INVALID_GEOMETRY_ID, primID = 0;
  float u = 0.0f, v = 0.0f;
  Vector3f ng = Vector3f::Zero();  // Embree's geometric normal, not normalised
};

// Closest Embree hit along the ray in (tnear, tfar), skipping clipped hits. Returns false for none.
bool intersectEmbree(const Frame& f, const Vector3f& origin, const Vector3f& direction, float tnear, float tfar,
                     RTCIntersectContext& context, Counters& counters, EmbreeHit& out) {
  for (int skip = 0; skip <= kMaxClipSkips; ++skip) {
    RTCRayHit rh{};
    rh.ray.org_x = origin.x(), rh.ray.org_y = origin.y(), rh.ray.org_z = origin.z();
    rh.ray.dir_x = direction.x(), rh.ray.dir_y = direction.y(), rh.ray.dir_z = direction.z();
    rh.ray.tnear = tnear;
    rh.ray.tfar = tfar;
    rh.ray.mask = 0xFFFFFFFFu;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(f.scene, &context, &rh);
    ++counters.total;
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;
    if (!clipped(f, origin + rh.ray.tfar * direction)) {
      out.t = rh.ray.tfar;
      out.geomID = rh.hit.geomID;
      out.primID = rh.hit.primID;
      out.u = rh.hit.u;
      out.v = rh.hit.v;
      out.ng = {rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z};
      return true;
    }
    tnear = rh.ray.tfar + f.epsilon;
  }
  return false;
}

// Whether anything in the Embree scene blocks the segment origin + t direction, t in (0, tfar).
bool occluded(const Frame& f, const Vector3f& origin, const Vector3f& direction, float tfar,
              RTCIntersectContext& context, Counters& counters) {
  if (f.input->clip.enabled) {
    EmbreeHit hit;
    return intersectEmbree(f, origin, direction, 0.0f, tfar, context, counters, hit);
  }
  RTCRay ray{};
  ray.org_x = origin.x(), ray.org_y = origin.y(), ray.org_z = origin.z();
  ray.dir_x = direction.x(), ray.dir_y = direction.y(), ray.dir_z = direction.z();
  ray.tnear = 0.0f;
  ray.tfar = tfar;
  ray.mask = 0xFFFFFFFFu;
  rtcOccluded1(f.scene, &context, &ray);
  ++counters.total;
  return ray.tfar == -kInfinity;  // Embree marks a hit by setting tfar to -inf
}

Vector3f groundAlbedo(const Frame& f, const Vector3f& point) {
  const Ground& g = f.input->ground;
  if (g.checkerSize <= 0.0f) return g.albedoA;
  const Vector3f offset = point - g.point;
  const double cells = std::floor(offset.dot(f.groundU) / g.checkerSize) + std::floor(offset.dot(f.groundV) / g.checkerSize);
  return std::fmod(std::abs(cells), 2.0) == 0.0 ? g.albedoA : g.albedoB;
}

// The surface hit `e` along the ray.
Hit embreeHit(const Frame& f, const Vector3f& origin, const Vector3f& direction, const EmbreeHit& e) {
  Hit hit;
  hit.kind = Hit::Surface;
  hit.t = e.t;
  hit.point = origin + e.t * direction;
  const Geometry& g = f.geometries[e.geomID];
  const unsigned primID = e.primID;
  const float u = e.u, v = e.v;
  if (g.curves) {
    const auto [t, index] = g.primitives[primID];
    const Tube& tube = g.curves->tubes[t];
    Vector3f centre;  // of the circle (tube) or sphere (cap) the hit lies on
    if (g.caps) {
      centre = index == 0 ? tube.points.front() : tube.points.back();
    } else {
      const int i = static_cast<int>(index);
      centre = bspline(tubeControlPoint(tube, i - 1), tubeControlPoint(tube, i), tubeControlPoint(tube, i + 1),
                       tubeControlPoint(tube, i + 2), std::clamp(u, 0.0f, 1.0f))
                   .head<3>();
    }
    // Embree's Ng of a round curve is the swept surface's normal (outward; the taper tilts it
    // along the curve), of a sphere the radial direction; both are made to point away from the
    // centre line, out of the tube, as the materials expect.
    const Vector3f radial = hit.point - centre;
    hit.ng = e.ng.normalized();
    if (!hit.ng.allFinite()) hit.ng = radial.normalized();
    else if (hit.ng.dot(radial) < 0.0f) hit.ng = -hit.ng;
    hit.ns = hit.ng;
    hit.material = &g.curves->material;
    hit.albedo = checkerAlbedo(g.curves->material, g.curves->material.albedo, hit.point);
    hit.objectId = tube.objectId != 0 ? tube.objectId : g.curves->objectId;
  } else if (g.mesh) {
    const TriangleMesh& mesh = *g.mesh->mesh;
    const Eigen::Vector3i& tri = mesh.triangles[primID];
    const Vector3f& p0 = mesh.positions[tri[0]];
    hit.ng = (mesh.positions[tri[1]] - p0).cross(mesh.positions[tri[2]] - p0).normalized();  // CCW: outward
    hit.ns = hit.ng;
    if (!mesh.normals.empty()) {  // smooth shading: barycentric interpolation of vertex normals
      const Vector3f n = (1.0f - u - v) * mesh.normals[tri[0]] + u * mesh.normals[tri[1]] + v * mesh.normals[tri[2]];
      if (n.squaredNorm() > 0.0f) hit.ns = n.normalized();
      if (hit.ns.dot(hit.ng) < 0.0f) hit.ng = -hit.ng;  // trust the level set's outward gradient
    }
    hit.material = &g.mesh->material;
    hit.albedo = checkerAlbedo(g.mesh->material, g.mesh->material.albedo, hit.point);
    hit.objectId = g.mesh->objectId;
  } else {
    const SphereSet& set = *g.spheres;
    hit.ng = (hit.point - set.centres[primID]).normalized();
    hit.ns = hit.ng;
    hit.material = &set.material;
    hit.albedo = set.colours.empty() ? set.material.albedo : set.colours[primID];
    hit.objectId = set.objectId;
  }
  if (!hit.ng.allFinite()) hit.ng = hit.ns = -direction;
  return hit;
}

// Closest hit among Embree geometry, the ground and the area lights.
Hit intersect(const Frame& f, const Vector3f& origin, const Vector3f& direction, RTCIntersectContext& context,
              Counters& counters) {
  Hit hit;
  EmbreeHit e;
  if (intersectEmbree(f, origin, direction, 0.0f, kInfinity, context, counters, e))
    hit = embreeHit(f, origin, direction, e);
  const Ground& ground = f.input->ground;
  if (ground.enabled) {
    const float denominator = direction.dot(f.groundNormal);
    if (denominator != 0.0f) {
      const float tg = (ground.point - origin).dot(f.groundNormal) / denominator;
      if (tg > 0.0f && tg < hit.t) {
        hit.kind = Hit::Ground;
        hit.t = tg;
        hit.point = origin + tg * direction;
        hit.ng = hit.ns = f.groundNormal;
        hit.material = nullptr;
        hit.albedo = groundAlbedo(f, hit.point);
        hit.objectId = kObjectGround;
      }
    }
  }
  const std::vector<RectLight>& lights = f.input->rectLights;
  for (size_t i = 0; i < lights.size(); ++i) {
    const RectLight& l = lights[i];
    const Vector3f n = l.edgeU.cross(l.edgeV);
    const float denominator = direction.dot(n);
    if (denominator == 0.0f) continue;
    const float tl = (l.corner - origin).dot(n) / denominator;
    if (!(tl > 0.0f && tl < hit.t)) continue;
    const Vector3f q = origin + tl * direction - l.corner;
    const float s = q.dot(l.edgeU) / l.edgeU.squaredNorm(), r = q.dot(l.edgeV) / l.edgeV.squaredNorm();
    if (s < 0.0f || s > 1.0f || r < 0.0f || r > 1.0f) continue;
    hit.kind = Hit::Light;
    hit.t = tl;
    hit.point = origin + tl * direction;
    hit.ng = hit.ns = n.normalized();
    hit.light = static_cast<int>(i);
    hit.objectId = kObjectLight;
  }
  return hit;
}

// Fraction of light that reaches `origin` along `direction` from distance tfar. Opaque hits
// give 0. With transmissive shadows the ray goes straight on through dielectric surfaces and
// stands for the refracted path that meets each surface at the same angle on the air's side
// (Snell's window): each crossing lets (1 - F) through, F taken at that angle from the air's side
// (so no total internal reflection: a wave facet steeper than the critical angle does not cast a
// black shadow, which the refracted light of its neighbours would fill), the medium absorbs
// exp(-absorption * length), and the radiance is divided by ior^2 for every medium the ray leaves
// and multiplied by it for every one it enters. A shading point under water thus receives 1/ior^2
// of what the unbent ray carries: the sky seen from under a flat surface is squeezed into a cone
// whose projected solid angle is 1/ior^2 of the hemisphere's, and a beam (the sun, a small light)
// crosses the same horizontal area, while the tracer does not scale radiance at refractions
// (materials.cpp), so the camera's path out of the water does not undo it. For a flat surface over
// a parallel floor the unbent ray then gives exactly the irradiance of the refracted paths
// (conservation of etendue, n^2 cos dw invariant); a ray through a parallel slab from air to air
// keeps (1 - F)^2, the slab's exact single-pass transmission.
Vector3f transmittance(const Frame& f, Vector3f origin, const Vector3f& direction, float tfar,
                       RTCIntersectContext& context, Counters& counters) {
  if (!f.settings->transmissiveShadows)
    return occluded(f, origin, direction, tfar, context, counters) ? Vector3f::Zero() : Vector3f::Ones();
  Vector3f through = Vector3f::Ones();
  float etendue = 1.0f;  // the product of ior^2 entered and 1/ior^2 left
  for (int crossing = 0; crossing < kMaxShadowCrossings; ++crossing) {
    EmbreeHit e;
    if (!intersectEmbree(f, origin, direction, 0.0f, tfar, context, counters, e)) return through * etendue;
    const Hit hit = embreeHit(f, origin, direction, e);
    const float t = e.t;
    const Material& m = *hit.material;
    if (m.type != MaterialType::Dielectric) return Vector3f::Zero();
    const float cosine = direction.dot(hit.ng);
    const bool leaving = cosine > 0.0f;  // the segment just travelled was inside
    through *= 1.0f - fresnelDielectric(std::abs(cosine), 1.0f, m.ior);
    if (leaving) through = through.cwiseProduct((-m.absorption * t).array().exp().matrix());
    etendue *= leaving ? 1.0f / (m.ior * m.ior) : m.ior * m.ior;
    if (through.maxCoeff() <= 0.0f) return Vector3f::Zero();
    origin = hit.point + (leaving ? f.epsilon : -f.epsilon) * hit.ng;
    tfar = tfar == kInfinity ? kInfinity : tfar - t;
    if (!(tfar > 0.0f)) return through * etendue;
  }
  return Vector3f::Zero();
}

// Whether the infinite ground stands in the way of the ray (shadow rays ignore it otherwise: it
// casts no shadows, but the sky below its horizon must not light anything above it).
bool groundBlocks(const Frame& f, const Vector3f& origin, const Vector3f& direction) {
  if (!f.input->ground.enabled) return false;
  const float denominator = direction.dot(f.groundNormal);
  return denominator != 0.0f && (f.input->ground.point - origin).dot(f.groundNormal) / denominator > 0.0f;
}

// Direct light from the sun and the area lights at a non-specular vertex (one sample each), and
// from the environment when it is sampled (one direction, MIS-weighted against BSDF sampling).
// `sunPart`, when given, receives the sun's share of the sum.
Vector3f directLight(const Frame& f, const Hit& hit, const Vector3f& wo, PixelSampler& rng,
                     RTCIntersectContext& context, Counters& counters, Vector3f* sunPart = nullptr) {
  static const Material kGroundMaterial{};
  const Material& material = hit.material ? *hit.material : kGroundMaterial;
  Vector3f sum = Vector3f::Zero();
  const auto origin = [&](const Vector3f& wi) {
    return Vector3f(hit.point + (wi.dot(hit.ng) > 0.0f ? f.epsilon : -f.epsilon) * hit.ng);
  };
  // Sun: a uniformly sampled direction in its cone; irradiance * f cos (the cone's pdf cancels).
  const float u1 = rng.next(), u2 = rng.next();
  if (f.sunOn) {
    const Vector3f wi = f.sunCosMax < 1.0f ? sampleCone(f.toSun, f.sunCosMax, u1, u2) : f.toSun;
    const Vector3f fcos = evaluateDiffuseLobe(material, hit.albedo, wo, wi, hit.ns, hit.ng);
    if (fcos.maxCoeff() > 0.0f)
      sum += fcos.cwiseProduct(f.input->sun.irradiance)
                 .cwiseProduct(transmittance(f, origin(wi), wi, kInfinity, context, counters));
  }
  if (sunPart) *sunPart = sum;
  // Area lights: a uniform point on each; pdf 1 / area converted to solid angle.
  for (const RectLight& l : f.input->rectLights) {
    const float s = rng.next(), r = rng.next();
    const Vector3f normal = l.edgeU.cross(l.edgeV);
    const float area = normal.norm();
    const Vector3f q = l.corner + s * l.edgeU + r * l.edgeV;
    const Vector3f d = q - hit.point;
    const float distance2 = d.squaredNorm();
    if (!(distance2 > 0.0f) || area == 0.0f) continue;
    const float distance = std::sqrt(distance2);
    const Vector3f wi = d / distance;
    const float cosLight = -wi.dot(normal) / area;
    if (cosLight <= 0.0f) continue;
    const Vector3f fcos = evaluateDiffuseLobe(material, hit.albedo, wo, wi, hit.ns, hit.ng);
    if (fcos.maxCoeff() > 0.0f)
      sum += fcos.cwiseProduct(l.radiance).cwiseProduct(
                 transmittance(f, origin(wi), wi, distance * (1.0f - 1e-4f), context, counters)) *
             (cosLight * area / distance2);
  }
  // Environment: a direction by luminance, weighted by the power heuristic against the BSDF's
  // pdf for the same direction (Veach 1997, ch. 9); tracePath gives escaping BSDF samples the
  // complementary weight.
  if (!f.environment.empty()) {
    const float e1 = rng.next(), e2 = rng.next();
    float pdfLight = 0.0f;
    const Vector3f wi = f.environment.sample(e1, e2, pdfLight);
    if (pdfLight > 0.0f) {
      const Vector3f fcos = evaluateDiffuseLobe(material, hit.albedo, wo, wi, hit.ns, hit.ng);
      if (fcos.maxCoeff() > 0.0f && !groundBlocks(f, hit.point, wi)) {
        const float weight = powerHeuristic(pdfLight, diffuseLobePdf(material, wo, wi, hit.ns, hit.ng)) / pdfLight;
        sum += fcos.cwiseProduct(environmentRadiance(f.input->environment, wi))
                   .cwiseProduct(transmittance(f, origin(wi), wi, kInfinity, context, counters)) *
               weight;
      }
    }
  }
  return sum;
}

// The denoiser's features of one camera path (denoise.h): albedo and normal at its first
// non-specular vertex, the albedo times the specular chain's throughput before it, and the sun's
// direct light there times that throughput (its share of the path's radiance).
struct PathFeatures {
  Vector3f albedo = Vector3f::Zero();
  Vector3f normal = Vector3f::Zero();
  Vector3f sun = Vector3f::Zero();
};

// Radiance along one camera ray; `hitSomething` tells whether the camera ray met geometry.
// `features`, when given, receives the path's denoiser features.
//
// With RenderSettings::fresnelSplitting, where the camera ray (firstDepth 0) first meets a
// dielectric from outside, both branches are followed: the reflected one as a path of its own
// (this function again, from depth 1) with weight F, the refracted one by this path with
// weight 1 - F, instead of choosing one with probabilities F and 1 - F. Same expectation, no
// noise from the choice (a splitting estimator, Arvo & Kirk 1990).
Vector3f tracePath(const Frame& f, Vector3f origin, Vector3f direction, PixelSampler& rng,
                   RTCIntersectContext& context, Counters& counters, bool& hitSomething,
                   PathFeatures* features = nullptr, int firstDepth = 0) {
  static const Material kGroundMaterial{};
  const RenderSettings& settings = *f.settings;
  Vector3f radiance = Vector3f::Zero();
  Vector3f throughput = Vector3f::Ones();
  Vector3f absorption = Vector3f::Zero();  // of the medium the ray travels in (0: air)
  bool specular = true;                    // the camera counts as a specular vertex
  bool cameraChain = true;                 // every vertex so far was specular
  bool refractedOnly = false;              // every vertex since the last diffuse one refracted
  float bsdfPdf = 0.0f;                    // pdf of the last scattering if it was not specular
  const bool sampledSky = !f.environment.empty();
  float splitFactor = 1.0f;                // 1 - F where the camera ray was split (fresnelSplitting)
  hitSomething = false;
  for (int depth = firstDepth;; ++depth) {
    const Hit hit = intersect(f, origin, direction, context, counters);
    if (depth == 0) hitSomething = hit.kind != Hit::None;
    if (hit.kind != Hit::None && absorption.maxCoeff() > 0.0f)
      throughput = throughput.cwiseProduct((-absorption * hit.t).array().exp().matrix());  // Beer-Lambert
    if (features && cameraChain && (hit.kind == Hit::None || hit.kind == Hit::Light)) features->albedo = throughput;
    if (hit.kind == Hit::None) {
      if (depth == 0 && settings.transparentBackground) break;
      // With the sky sampled as a light: escaping straight from a diffuse vertex takes the power
      // heuristic's weight; through a chain of refractions only it was counted by the unbent
      // shadow ray already (transmissive shadows).
      float weight = 1.0f;
      if (sampledSky && !cameraChain) {
        if (!specular && bsdfPdf > 0.0f && !refractedOnly)
          weight = powerHeuristic(bsdfPdf, f.environment.pdf(direction));
        else if (refractedOnly && settings.transmissiveShadows)
          weight = 0.0f;
      }
      if (weight > 0.0f)
        radiance += throughput.cwiseProduct(environmentRadiance(f.input->environment, direction)) * weight;
      if (specular && f.sunOn && f.sunCosMax < 1.0f && direction.dot(f.toSun) >= f.sunCosMax)
        radiance += throughput.cwiseProduct(f.sunRadiance);
      break;
    }
    if (hit.kind == Hit::Light) {
      if (specular && direction.dot(hit.ng) < 0.0f)
        radiance += throughput.cwiseProduct(f.input->rectLights[size_t(hit.light)].radiance);
      break;
    }
    if (depth >= settings.maxDepth) break;
    const Material& material = hit.material ? *hit.material : kGroundMaterial;
    const Vector3f wo = -direction;
    if (features && cameraChain && hasDiffuseLobe(material.type)) {
      features->albedo = throughput.cwiseProduct(hit.albedo);
      features->normal = wo.dot(hit.ng) >= 0.0f ? hit.ns : Vector3f(-hit.ns);
    }
    if (hasDiffuseLobe(material.type)) {
      const bool first = features && cameraChain;
      Vector3f sun = Vector3f::Zero();
      radiance += throughput.cwiseProduct(directLight(f, hit, wo, rng, context, counters, first ? &sun : nullptr));
      if (first) features->sun = throughput.cwiseProduct(sun);
    } else
      rng.next(), rng.next();  // keep the dimension count independent of the material
    for (size_t i = 0; i < f.input->rectLights.size() && !hasDiffuseLobe(material.type); ++i) rng.next(), rng.next();
    if (sampledSky && !hasDiffuseLobe(material.type)) rng.next(), rng.next();

    ScatterSample s;
    float u1 = rng.next();
    const float u2 = rng.next(), u3 = rng.next();
    if (depth == 0 && settings.fresnelSplitting && material.type == MaterialType::Dielectric &&
        wo.dot(hit.ng) > 0.0f) {
      float cosO = wo.dot(hit.ns);
      if (!(cosO > 1e-6f)) cosO = std::max(wo.dot(hit.ng), 1e-6f);
      const float fresnel = fresnelDielectric(cosO, 1.0f, material.ior);
      if (fresnel > 0.0f && fresnel < 1.0f &&
          sampleMaterial(material, hit.albedo, wo, hit.ns, hit.ng, 0.0f, u2, u3, s) && !s.transmitted) {
        bool ignored = false;
        const Vector3f start = hit.point + (s.direction.dot(hit.ng) > 0.0f ? f.epsilon : -f.epsilon) * hit.ng;
        radiance += fresnel * throughput.cwiseProduct(
                                  tracePath(f, start, s.direction, rng, context, counters, ignored, nullptr, 1));
        throughput *= 1.0f - fresnel;
        splitFactor = 1.0f - fresnel;
        u1 = 1.0f - 0x1p-24f;  // this path refracts
      }
    }
    if (!sampleMaterial(material, hit.albedo, wo, hit.ns, hit.ng, u1, u2, u3, s)) break;
    throughput = throughput.cwiseProduct(s.weight);
    // With transmissive shadows, light behind a diffuse vertex and a chain of specular ones was
    // already estimated by the shadow ray through the dielectric: count lights on hit only for
    // pure specular chains from the camera.
    specular = s.specular && (cameraChain || !settings.transmissiveShadows);
    cameraChain = cameraChain && s.specular;
    if (!s.specular) {
      bsdfPdf = diffuseLobePdf(material, wo, s.direction, hit.ns, hit.ng);
      refractedOnly = false;
    } else {
      const bool refracted = s.transmitted && material.type == MaterialType::Dielectric;
      refractedOnly = (refractedOnly || bsdfPdf > 0.0f) && refracted;
      bsdfPdf = 0.0f;
    }
    if (s.transmitted && hit.material) {  // crossing the surface: entering if wo was outside
      const bool entering = wo.dot(hit.ng) > 0.0f;
      absorption = entering ? material.absorption : Vector3f::Zero();
    }
    origin = hit.point + (s.direction.dot(hit.ng) > 0.0f ? f.epsilon : -f.epsilon) * hit.ng;
    direction = s.direction;

    // Russian roulette once the throughput drops below 1 (not counting the split's deterministic
    // factor, which would only add the roulette's noise to what splitting removed)
    const float survival = throughput.maxCoeff() / splitFactor;
    const float u = rng.next();
    if (depth >= 2 && survival < 1.0f) {
      if (u >= survival) break;
      throughput /= survival;
    }
  }
  return radiance;
}

// Whitted integrator (see Integrator in tracer.h). Direct light at a diffuse point, no noise:
// the sun along its centre direction, each area light at the centres of an n x n grid, the sky
// along the frame's fixed cosine-distributed directions about the shading normal that belong to
// the pixel's sample `sample` (Frame::skySet), turned to wo's side (cosine weighting cancels the
// cosine: sum L T / K estimates E / pi).
Vector3f whittedDirect(const Frame& f, const Hit& hit, const Material& material, const Vector3f& albedo,
                       const Vector3f& wo, int sample, RTCIntersectContext& context, Counters& counters) {
  const bool outside = wo.dot(hit.ng) >= 0.0f;
  const Vector3f g = outside ? hit.ng : Vector3f(-hit.ng);
  Vector3f n = outside ? hit.ns : Vector3f(-hit.ns);
  if (!(wo.dot(n) > 1e-6f)) n = g;
  const auto origin = [&](const Vector3f& wi) {
    return Vector3f(hit.point + (wi.dot(hit.ng) > 0.0f ? f.epsilon : -f.epsilon) * hit.ng);
  };
  const float invPi = 1.0f / std::numbers::pi_v<float>;
  const auto fcos = [&](const Vector3f& wi) {
    return wi.dot(g) > 0.0f ? Vector3f(albedo * (invPi * std::max(0.0f, wi.dot(n)))) : Vector3f::Zero();
  };
  (void)material;
  Vector3f sum = Vector3f::Zero();
  if (f.sunOn) {
    const Vector3f c = fcos(f.toSun);
    if (c.maxCoeff() > 0.0f)
      sum += c.cwiseProduct(f.input->sun.irradiance)
                 .cwiseProduct(transmittance(f, origin(f.toSun), f.toSun, kInfinity, context, counters));
  }
  const int grid = f.settings->whitted.lightSamples;
  for (const RectLight& l : f.input->rectLights) {
    const Vector3f normal = l.edgeU.cross(l.edgeV);
    const float area = normal.norm();
    if (area == 0.0f) continue;
    for (int j = 0; j < grid; ++j)
      for (int i = 0; i < grid; ++i) {
        const Vector3f q = l.corner + (float(i) + 0.5f) / float(grid) * l.edgeU + (float(j) + 0.5f) / float(grid) * l.edgeV;
        const Vector3f d = q - hit.point;
        const float distance2 = d.squaredNorm();
        if (!(distance2 > 0.0f)) continue;
        const float distance = std::sqrt(distance2);
        const Vector3f wi = d / distance;
        const float cosLight = -wi.dot(normal) / area;
        const Vector3f c = fcos(wi);
        if (cosLight <= 0.0f || c.maxCoeff() <= 0.0f) continue;
        sum += c.cwiseProduct(l.radiance).cwiseProduct(
                   transmittance(f, origin(wi), wi, distance * (1.0f - 1e-4f), context, counters)) *
               (cosLight * area / (distance2 * float(grid * grid)));
      }
  }
  Vector3f sky = Vector3f::Zero();
  for (size_t k = size_t(sample % f.skySamples); k < f.skySet.size(); k += size_t(f.skySamples)) {
    const Eigen::Vector2f& u = f.skySet[k];
    const Vector3f wi = sampleCosineHemisphere(n, u.x(), u.y());
    if (wi.dot(g) <= 0.0f || groundBlocks(f, hit.point, wi)) continue;
    sky += environmentRadiance(f.input->environment, wi)
               .cwiseProduct(transmittance(f, origin(wi), wi, kInfinity, context, counters));
  }
  if (!f.skySet.empty()) sum += albedo.cwiseProduct(sky) * (float(f.skySamples) / float(f.skySet.size()));
  return sum;
}

constexpr float kWhittedCutoff = 1e-3f;  // branches whose weight falls below this are dropped

// Radiance along a ray by the Whitted integrator; `weight` is the product of the Fresnel and
// mirror factors so far (for the cutoff), `absorption` the medium's coefficient (0: air).
Vector3f traceWhitted(const Frame& f, const Vector3f& origin, const Vector3f& direction, int depth,
                      const Vector3f& absorption, float weight, int sample, RTCIntersectContext& context,
                      Counters& counters, bool* hitSomething) {
  static const Material kGroundMaterial{};
  const Hit hit = intersect(f, origin, direction, context, counters);
  if (hitSomething) *hitSomething = hit.kind != Hit::None;
  if (hit.kind == Hit::None) {
    if (depth == 0 && f.settings->transparentBackground) return Vector3f::Zero();
    Vector3f l = environmentRadiance(f.input->environment, direction);
    if (f.sunOn && f.sunCosMax < 1.0f && direction.dot(f.toSun) >= f.sunCosMax) l += f.sunRadiance;
    return l;
  }
  const Vector3f attenuation =
      absorption.maxCoeff() > 0.0f ? Vector3f((-absorption * hit.t).array().exp().matrix()) : Vector3f::Ones();
  if (hit.kind == Hit::Light)
    return direction.dot(hit.ng) < 0.0f
               ? Vector3f(attenuation.cwiseProduct(f.input->rectLights[size_t(hit.light)].radiance))
               : Vector3f::Zero();
  if (depth >= f.settings->maxDepth) return Vector3f::Zero();
  const Material& material = hit.material ? *hit.material : kGroundMaterial;
  const Vector3f wo = -direction;
  Vector3f radiance = Vector3f::Zero();
  const auto follow = [&](const ScatterSample& s, const Vector3f& factor) {
    const float branch = weight * factor.maxCoeff();
    if (!(branch >= kWhittedCutoff)) return;
    Vector3f medium = absorption;
    if (s.transmitted && hit.material) medium = wo.dot(hit.ng) > 0.0f ? material.absorption : Vector3f::Zero();
    const Vector3f next = hit.point + (s.direction.dot(hit.ng) > 0.0f ? f.epsilon : -f.epsilon) * hit.ng;
    radiance += factor.cwiseProduct(
        traceWhitted(f, next, s.direction, depth + 1, medium, branch, sample, context, counters, nullptr));
  };
  // Fresnel reflectance for wo at this interface (as materials.cpp's facing frame computes it).
  const auto fresnel = [&] {
    const bool outside = wo.dot(hit.ng) >= 0.0f;
    float cosO = wo.dot(outside ? hit.ns : Vector3f(-hit.ns));
    if (!(cosO > 1e-6f)) cosO = std::max(std::abs(wo.dot(hit.ng)), 1e-6f);
    return fresnelDielectric(cosO, outside ? 1.0f : material.ior, outside ? material.ior : 1.0f);
  };
  ScatterSample s;
  constexpr float kAlmostOne = 1.0f - 0x1p-24f;
  switch (material.type) {
    case MaterialType::Diffuse:
      radiance = whittedDirect(f, hit, material, hit.albedo, wo, sample, context, counters);
      break;
    case MaterialType::Mirror:
      if (sampleMaterial(material, hit.albedo, wo, hit.ns, hit.ng, 0.0f, 0.5f, 0.5f, s)) follow(s, s.weight);
      break;
    case MaterialType::Dielectric: {
      const float F = fresnel();
      if (F > 0.0f && sampleMaterial(material, hit.albedo, wo, hit.ns, hit.ng, 0.0f, 0.5f, 0.5f, s))
        follow(s, Vector3f::Constant(F));
      if (F < 1.0f && sampleMaterial(material, hit.albedo, wo, hit.ns, hit.ng, kAlmostOne, 0.5f, 0.5f, s))
        follow(s, Vector3f::Constant(1.0f - F));
      break;
    }
    case MaterialType::Translucent: {
      const float F = fresnel();
      if (F > 0.0f && sampleMaterial(material, hit.albedo, wo, hit.ns, hit.ng, 0.0f, 0.5f, 0.5f, s) && !s.transmitted)
        follow(s, Vector3f::Constant(F));
      radiance += whittedDirect(f, hit, material, hit.albedo.cwiseProduct(hit.albedo) * (1.0f - F), wo, sample, context,
                                counters);
      break;
    }
  }
  return attenuation.cwiseProduct(radiance);
}

// The compositing layers (frame_layers.h): one ray through each pixel centre and the lens centre.
FrameLayers firstHitLayers(const Frame& f, const CameraRays& camera, int width, int height) {
  FrameLayers layers(width, height);
  tbb::parallel_for(tbb::blocked_range<int>(0, height), [&](const tbb::blocked_range<int>& rows) {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    Counters counters;
    for (int y = rows.begin(); y != rows.end(); ++y)
      for (int x = 0; x < width; ++x) {
        Vector3f origin, direction;
        camera.generate(float(x) + 0.5f, float(y) + 0.5f, 0.5f, 0.5f, origin, direction);
        const Hit hit = intersect(f, origin, direction, context, counters);
        if (hit.kind == Hit::None) continue;
        const size_t i = layers.index(x, y);
        layers.depth[i] = hit.t * direction.dot(camera.forward());
        layers.normal[i] = hit.ns.dot(direction) > 0.0f ? Vector3f(-hit.ns) : hit.ns;
        if (hit.kind == Hit::Light) layers.albedo[i] = Vector3f::Zero();
        else if (hit.material && hit.material->type == MaterialType::Dielectric) layers.albedo[i] = Vector3f::Ones();
        else layers.albedo[i] = hit.albedo;
        layers.objectId[i] = hit.objectId;
      }
  });
  return layers;
}

}  // namespace

Image renderFrame(const RenderScene& scene, const RenderSettings& settings, RenderStats* stats,
                  FrameLayers* layers) {
  const auto start = std::chrono::steady_clock::now();
  if (settings.width <= 0 || settings.height <= 0 || settings.samplesPerPixel <= 0)
    throw std::invalid_argument("renderFrame: width, height and samplesPerPixel must be positive");
  if (settings.maxDepth < 1) throw std::invalid_argument("renderFrame: maxDepth must be >= 1");
  if (settings.whitted.skyDirections < 1 || settings.whitted.lightSamples < 1)
    throw std::invalid_argument("renderFrame: whitted skyDirections and lightSamples must be >= 1");
  if (settings.adaptive.enabled &&
      !(settings.adaptive.relativeError > 0.0f && settings.adaptive.minSamples >= 2 &&
        settings.adaptive.maxSamples >= settings.adaptive.minSamples))
    throw std::invalid_argument("renderFrame: adaptive sampling needs relativeError > 0 and 2 <= minSamples <= maxSamples");
  if (scene.sun.direction.squaredNorm() == 0.0f) throw std::invalid_argument("renderFrame: zero sun direction");
  if (!(scene.sun.angularDiameterDegrees >= 0.0f && scene.sun.angularDiameterDegrees < 90.0f))
    throw std::invalid_argument("renderFrame: sun angular diameter must be in [0, 90) degrees");
  if (scene.ground.enabled && scene.ground.normal.squaredNorm() == 0.0f)
    throw std::invalid_argument("renderFrame: zero ground normal");
  if (scene.clip.enabled && scene.clip.normal.squaredNorm() == 0.0f)
    throw std::invalid_argument("renderFrame: zero clip plane normal");
  if (scene.environment.type == EnvironmentType::Image && !scene.environment.image)
    throw std::invalid_argument("renderFrame: image environment without an image");
  const CameraRays camera(scene.camera, settings.width, settings.height);

  EmbreeErrors errors;
  DevicePtr device = newDevice();
  rtcSetDeviceErrorFunction(device.get(), onEmbreeError, &errors);
  ScenePtr embreeScene(rtcNewScene(device.get()), &rtcReleaseScene);
  Frame frame;
  frame.input = &scene;
  frame.settings = &settings;
  // Scene scale for the self-intersection offset: largest coordinate magnitude in view.
  float scale = std::max(scene.camera.position.cwiseAbs().maxCoeff(),
                         scene.ground.enabled ? scene.ground.point.cwiseAbs().maxCoeff() : 0.0f);
  for (size_t i = 0; i < scene.meshes.size(); ++i) {
    const std::string name = "mesh " + std::to_string(i);
    if (!scene.meshes[i].mesh) throw std::invalid_argument("renderFrame: " + name + " has no mesh");
    checkMaterial(scene.meshes[i].material, name);
    if (scene.meshes[i].mesh->triangles.empty()) continue;  // nothing to hit
    addMesh(device.get(), embreeScene.get(), *scene.meshes[i].mesh, unsigned(frame.geometries.size()), name);
    frame.geometries.push_back({&scene.meshes[i], nullptr, nullptr, false, {}, nullptr});
    for (const Vector3f& p : scene.meshes[i].mesh->positions) scale = std::max(scale, p.cwiseAbs().maxCoeff());
  }
  for (size_t i = 0; i < scene.spheres.size(); ++i) {
    const std::string name = "sphere set " + std::to_string(i);
    checkMaterial(scene.spheres[i].material, name);
    if (scene.spheres[i].centres.empty()) continue;
    addSpheres(device.get(), embreeScene.get(), scene.spheres[i], unsigned(frame.geometries.size()), name);
    frame.geometries.push_back({nullptr, &scene.spheres[i], nullptr, false, {}, nullptr});
    for (const Vector3f& p : scene.spheres[i].centres) scale = std::max(scale, p.cwiseAbs().maxCoeff());
  }
  for (size_t i = 0; i < scene.curves.size(); ++i) {
    const CurveSet& set = scene.curves[i];
    const std::string name = "curve set " + std::to_string(i);
    checkMaterial(set.material, name);
    checkCurves(set, name);
    if (std::none_of(set.tubes.begin(), set.tubes.end(), [](const Tube& t) { return t.points.size() >= 2; }))
      continue;  // nothing to hit
    Geometry curves{nullptr, nullptr, &set, false, {}, nullptr};
    Geometry caps{nullptr, nullptr, &set, true, {}, std::make_unique<std::vector<CapPlane>>()};
    const auto curveID = unsigned(frame.geometries.size());
    addCurves(device.get(), embreeScene.get(), set, curveID, curveID + 1, curves.primitives, caps.primitives,
              *caps.capPlanes);
    frame.geometries.push_back(std::move(curves));
    frame.geometries.push_back(std::move(caps));
    for (const Tube& tube : set.tubes)
      for (const Vector3f& p : tube.points) scale = std::max(scale, p.cwiseAbs().maxCoeff());
  }
  // High-quality BVHs (SAH with spatial splits): builds cost more, traversal less; on the
  // jellyfish's preview frame the path tracer's frame time fell about 10 % (build included).
  rtcSetSceneBuildQuality(embreeScene.get(), RTC_BUILD_QUALITY_HIGH);
  rtcCommitScene(embreeScene.get());
  throwIfError(device.get(), errors, "scene build");

  frame.scene = embreeScene.get();
  frame.toSun = -scene.sun.direction.normalized();
  const float sunRadius = 0.5f * scene.sun.angularDiameterDegrees * std::numbers::pi_v<float> / 180.0f;
  frame.sunCosMax = std::cos(sunRadius);
  const float sunSolidAngle = 2.0f * std::numbers::pi_v<float> * (1.0f - frame.sunCosMax);
  frame.sunRadiance = sunSolidAngle > 0.0f ? Vector3f(scene.sun.irradiance / sunSolidAngle) : Vector3f::Zero();
  frame.sunOn = scene.sun.irradiance.maxCoeff() > 0.0f;
  frame.epsilon = 1e-4f * std::max(1.0f, scale);
  if (scene.ground.enabled) {
    frame.groundNormal = scene.ground.normal.normalized();
    const Vector3f axis = std::abs(frame.groundNormal.x()) < 0.9f ? Vector3f::UnitX() : Vector3f::UnitY();
    frame.groundU = (axis - frame.groundNormal.dot(axis) * frame.groundNormal).normalized();
    frame.groundV = frame.groundNormal.cross(frame.groundU);
  }
  if (scene.clip.enabled) frame.clipNormal = scene.clip.normal.normalized();
  const bool whitted = settings.integrator == Integrator::Whitted;
  if (settings.environmentSampling && !whitted)
    frame.environment = EnvironmentSampler(scene.environment, scene.ground.enabled ? &frame.groundNormal : nullptr);
  if (whitted) {  // fixed Hammersley points, shifted half a stratum off the pole
    frame.skySamples = std::max(1, settings.samplesPerPixel);
    const int points = settings.whitted.skyDirections * frame.skySamples;
    for (int k = 0; k < points; ++k) {
      const float v = radicalInverse2(uint32_t(k)) + 0.5f / float(points);
      frame.skySet.emplace_back((float(k) + 0.5f) / float(points), v - std::floor(v));
    }
  }

  Image image(settings.width, settings.height);
  const int tilesX = (settings.width + kTileSize - 1) / kTileSize;
  const int tilesY = (settings.height + kTileSize - 1) / kTileSize;
  const int nFixed = settings.samplesPerPixel;
  const AdaptiveSettings adaptive = settings.adaptive;
  std::atomic<uint64_t> primaryRays{0}, totalRays{0}, samples{0};
  const bool denoising = settings.denoise.enabled && !whitted;
  FeatureBuffers features;
  if (denoising) {
    features.width = settings.width;
    features.height = settings.height;
    features.albedo.assign(size_t(settings.width) * size_t(settings.height), Vector3f::Zero());
    features.normal = features.albedo;
    features.sun = features.albedo;
  }
  tbb::parallel_for(tbb::blocked_range<int>(0, tilesX * tilesY), [&](const tbb::blocked_range<int>& tiles) {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    Counters counters;
    for (int tile = tiles.begin(); tile != tiles.end(); ++tile) {
      const int x0 = (tile % tilesX) * kTileSize, y0 = (tile / tilesX) * kTileSize;
      for (int y = y0; y < std::min(y0 + kTileSize, settings.height); ++y)
        for (int x = x0; x < std::min(x0 + kTileSize, settings.width); ++x) {
          const uint32_t pixel = static_cast<uint32_t>(y) * static_cast<uint32_t>(settings.width) + static_cast<uint32_t>(x);
          Vector3f sum = Vector3f::Zero(), albedoSum = Vector3f::Zero(), normalSum = Vector3f::Zero(),
                   sunSum = Vector3f::Zero();
          int covered = 0;
          int n = nFixed;
          // One path through sub-pixel `offset`: added to the pixel's sums; returns its radiance.
          const auto pathSample = [&](int s, const Vector2f& offset) {
            PixelSampler rng(pixel, static_cast<uint32_t>(s), static_cast<uint32_t>(settings.seed));
            const float lens1 = rng.next(), lens2 = rng.next();
            Vector3f origin, direction;
            camera.generate(static_cast<float>(x) + offset.x(), static_cast<float>(y) + offset.y(), lens1, lens2, origin,
                            direction);
            ++counters.primary;
            bool hitSomething = false;
            PathFeatures pf;
            const Vector3f value =
                tracePath(frame, origin, direction, rng, context, counters, hitSomething, denoising ? &pf : nullptr);
            sum += value;
            albedoSum += pf.albedo;
            normalSum += pf.normal;
            sunSum += pf.sun;
            covered += hitSomething ? 1 : 0;
            return value;
          };
          if (whitted) {
            // Fixed sub-pixel positions (a Hammersley set, half a stratum in) and lens points.
            for (int s = 0; s < n; ++s) {
              const float sx = (float(s) + 0.5f) / float(n);
              float sy = radicalInverse2(uint32_t(s)) + 0.5f / float(n);
              sy -= std::floor(sy);
              Vector3f origin, direction;
              camera.generate(float(x) + sx, float(y) + sy, sy, sx, origin, direction);
              ++counters.primary;
              bool hitSomething = false;
              sum += traceWhitted(frame, origin, direction, 0, Vector3f::Zero(), 1.0f, s, context, counters,
                                  &hitSomething);
              covered += hitSomething ? 1 : 0;
            }
          } else if (adaptive.enabled) {
            // Batches of minSamples until the standard error of the mean luminance is small
            // enough relative to the mean (AdaptiveSettings).
            double lumSum = 0.0, lumSquares = 0.0;
            n = 0;
            while (n < adaptive.maxSamples) {
              const int batchEnd = std::min(n + adaptive.minSamples, adaptive.maxSamples);
              for (int s = n; s < batchEnd; ++s) {
                const Vector3f value =
                    pathSample(s, pixelSamplePositionProgressive(uint32_t(s), pixel, static_cast<uint32_t>(settings.seed)));
                const double lum = 0.2126 * value.x() + 0.7152 * value.y() + 0.0722 * value.z();
                lumSum += lum;
                lumSquares += lum * lum;
              }
              n = batchEnd;
              const double mean = lumSum / n;
              const double variance = std::max(0.0, (lumSquares - n * mean * mean) / (n - 1));
              if (std::sqrt(variance / n) <= adaptive.relativeError * std::max(mean, 0.05)) break;
            }
          } else {
            for (int s = 0; s < n; ++s)
              pathSample(s, pixelSamplePosition(uint32_t(s), uint32_t(n), pixel, static_cast<uint32_t>(settings.seed)));
          }
          if (denoising) {
            features.albedo[pixel] = albedoSum / float(n);
            features.normal[pixel] = normalSum / float(n);
            // normalised as the pixel's colour is, of which it is a part
            const int parts = settings.transparentBackground ? covered : n;
            features.sun[pixel] = parts > 0 ? Vector3f(sunSum / float(parts)) : Vector3f::Zero();
          }
          counters.samples += uint64_t(n);
          Eigen::Vector4f pixelValue(0, 0, 0, 1);
          if (settings.transparentBackground) {
            pixelValue[3] = static_cast<float>(covered) / static_cast<float>(n);
            if (covered > 0) pixelValue.head<3>() = sum / static_cast<float>(covered);  // straight alpha
          } else {
            pixelValue.head<3>() = sum / static_cast<float>(n);
          }
          image.at(x, y) = pixelValue;
        }
    }
    primaryRays += counters.primary;
    totalRays += counters.total;
    samples += counters.samples;
  });
  throwIfError(device.get(), errors, "rendering");
  if (denoising)
    image = denoise(image, features, settings.denoise,
                    std::max(1.0, double(samples.load()) / (double(settings.width) * double(settings.height))));
  if (layers) {
    std::vector<std::string> names = std::move(layers->objectNames);
    *layers = firstHitLayers(frame, camera, settings.width, settings.height);
    layers->objectNames = std::move(names);
    throwIfError(device.get(), errors, "layers");
  }
  if (stats) {
    stats->primaryRays = primaryRays;
    stats->totalRays = totalRays;
    stats->samples = samples;
    stats->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  return image;
}

std::string embreeVersion() {
  DevicePtr device = newDevice();
  const auto version = rtcGetDeviceProperty(device.get(), RTC_DEVICE_PROPERTY_VERSION);  // e.g. 31305
  return std::to_string(version / 10000) + "." + std::to_string(version / 100 % 100) + "." +
         std::to_string(version % 100);
}

}  // namespace kurage::render
