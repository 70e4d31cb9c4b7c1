// Embree 3 geometry and queries; see embree_scene.h. Buffers are copied into Embree-allocated,
// correctly padded storage.
#include "render/embree_scene.h"

#include <Eigen/Geometry>

#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>
#include <mutex>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace kurage::render {
namespace {

using Eigen::Vector3f;

constexpr float kInfinity = std::numeric_limits<float>::infinity();
constexpr int kMaxClipSkips = 64;  // clipped hits skipped along one ray before giving up

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

void checkMaterial(const Material& m, const std::string& name) {
  if (!(m.ior >= 1.0f && m.ior <= 4.0f)) throw std::invalid_argument(name + ": ior must be in [1, 4]");
  if (!(m.absorption.minCoeff() >= 0.0f)) throw std::invalid_argument(name + ": absorption must be >= 0");
  if (!(m.albedo.minCoeff() >= 0.0f && m.albedo.maxCoeff() <= 1.0f && m.albedoB.minCoeff() >= 0.0f &&
        m.albedoB.maxCoeff() <= 1.0f))
    throw std::invalid_argument(name + ": albedo must be in [0, 1]");
}

void checkMesh(const TriangleMesh& mesh, const std::string& name) {
  if (!mesh.normals.empty() && mesh.normals.size() != mesh.positions.size())
    throw std::invalid_argument(name + ": normals must be empty or one per position");
  for (const Eigen::Vector3i& t : mesh.triangles)
    if (t.minCoeff() < 0 || static_cast<size_t>(t.maxCoeff()) >= mesh.positions.size())
      throw std::invalid_argument(name + ": triangle index out of range");
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

float largestCoordinate(const std::vector<Vector3f>& points) {
  float scale = 0.0f;
  for (const Vector3f& p : points) scale = std::max(scale, p.cwiseAbs().maxCoeff());
  return scale;
}

void attach(RTCScene scene, RTCGeometry geometry, unsigned geomID) {
  rtcCommitGeometry(geometry);
  rtcAttachGeometryByID(scene, geometry, geomID);
  rtcReleaseGeometry(geometry);
}

using GeometryPtr = std::unique_ptr<RTCGeometryTy, decltype(&rtcReleaseGeometry)>;

// One mesh copied into a committed Embree triangle geometry.
GeometryPtr meshGeometry(RTCDevice device, const TriangleMesh& mesh) {
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
  return GeometryPtr(geometry, &rtcReleaseGeometry);
}

void addSpheres(RTCDevice device, RTCScene scene, const SphereSet& set, unsigned geomID) {
  RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_SPHERE_POINT);
  auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(
      geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4, 4 * sizeof(float), set.centres.size()));
  if (vertices)
    for (size_t i = 0; i < set.centres.size(); ++i) {
      for (int k = 0; k < 3; ++k) vertices[4 * i + k] = set.centres[i][k];
      vertices[4 * i + 3] = set.radius;
    }
  attach(scene, geometry, geomID);
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
  attach(scene, curves, curveID);
  attach(scene, spheres, capID);
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

const Material& geometryMaterial(const Geometry& g) {
  return g.curves ? g.curves->material : g.mesh ? g.mesh->material : g.spheres->material;
}

// The unit geometric and shading normals of a hit at `point` on primitive primID of `g` (u, v and
// embreeNg: Embree's hit coordinates and normal), pointing out of the object; -direction where
// the geometry gives none.
void hitNormals(const Geometry& g, unsigned primID, float u, float v, const Vector3f& point, const Vector3f& embreeNg,
                const Vector3f& direction, Vector3f& ng, Vector3f& ns) {
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
    const Vector3f radial = point - centre;
    ng = embreeNg.normalized();
    if (!ng.allFinite()) ng = radial.normalized();
    else if (ng.dot(radial) < 0.0f) ng = -ng;
    ns = ng;
  } else if (g.mesh) {
    const TriangleMesh& mesh = *g.mesh->mesh;
    const Eigen::Vector3i& tri = mesh.triangles[primID];
    const Vector3f& p0 = mesh.positions[tri[0]];
    ng = (mesh.positions[tri[1]] - p0).cross(mesh.positions[tri[2]] - p0).normalized();  // CCW: outward
    ns = ng;
    if (!mesh.normals.empty()) {  // smooth shading: barycentric interpolation of vertex normals
      const Vector3f n = (1.0f - u - v) * mesh.normals[tri[0]] + u * mesh.normals[tri[1]] + v * mesh.normals[tri[2]];
      if (n.squaredNorm() > 0.0f) ns = n.normalized();
      if (ns.dot(ng) < 0.0f) ng = -ng;  // trust the level set's outward gradient
    }
  } else {
    ng = (point - g.spheres->centres[primID]).normalized();
    ns = ng;
  }
  if (!ng.allFinite()) ng = ns = -direction;
}

// An Embree ray for an occlusion query of origin + t direction, t in (0, tfar).
RTCRay segment(const Vector3f& origin, const Vector3f& direction, float tfar) {
  RTCRay ray{};
  ray.org_x = origin.x(), ray.org_y = origin.y(), ray.org_z = origin.z();
  ray.dir_x = direction.x(), ray.dir_y = direction.y(), ray.dir_z = direction.z();
  ray.tnear = 0.0f;
  ray.tfar = tfar;
  ray.mask = 0xFFFFFFFFu;
  return ray;
}

// An occlusion query collecting the dielectric surfaces along its ray (EmbreeScene::crossings).
// Embree hands the filter the context's address, so the context comes first.
struct CrossingQuery {
  RTCIntersectContext context;
  const std::vector<Geometry>* geometries = nullptr;
  bool clipOn = false;
  Vector3f clipPoint, clipNormal;
  float epsilon = 0.0f;
  Vector3f origin, direction;
  Crossing* out = nullptr;
  int capacity = 0, count = 0;
};

// The context filter of CrossingQuery (after the geometry's own, capFilter): rejects clipped hits
// and records and rejects dielectric ones; any other hit, or one more crossing than there is room
// for, is accepted and ends the query as occluded.
void crossingFilter(const RTCFilterFunctionNArguments* args) {
  auto* query = reinterpret_cast<CrossingQuery*>(args->context);
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] == 0) continue;
    const float t = RTCRayN_tfar(args->ray, args->N, i);
    const Vector3f point = query->origin + t * query->direction;
    if (query->clipOn && (point - query->clipPoint).dot(query->clipNormal) > 0.0f) {
      args->valid[i] = 0;
      continue;
    }
    const unsigned geomID = RTCHitN_geomID(args->hit, args->N, i);
    const Geometry& g = (*query->geometries)[geomID];
    const Material& material = geometryMaterial(g);
    if (material.type != MaterialType::Dielectric) continue;  // opaque: occluded
    bool seen = false;
    for (int k = 0; k < query->count && !seen; ++k)
      seen = query->out[k].geomID == geomID && std::abs(query->out[k].t - t) <= query->epsilon;
    if (seen) {
      args->valid[i] = 0;
      continue;
    }
    if (query->count == query->capacity) continue;  // too many: occluded
    Crossing& c = query->out[query->count++];
    c.t = t;
    c.material = &material;
    c.geomID = geomID;
    Vector3f ns;
    const Vector3f embreeNg(RTCHitN_Ng_x(args->hit, args->N, i), RTCHitN_Ng_y(args->hit, args->N, i),
                            RTCHitN_Ng_z(args->hit, args->N, i));
    hitNormals(g, RTCHitN_primID(args->hit, args->N, i), RTCHitN_u(args->hit, args->N, i),
               RTCHitN_v(args->hit, args->N, i), point, embreeNg, query->direction, c.ng, ns);
    args->valid[i] = 0;
  }
}

// The static meshes: owned copies, the committed Embree geometries of those with triangles and
// what each refers to, and their largest coordinate magnitude.
struct StaticMeshes {
  std::vector<std::unique_ptr<TriangleMesh>> meshes;
  std::vector<SceneObject> objects;  // their mesh points into `meshes`
  std::vector<GeometryPtr> embree;
  std::vector<const SceneObject*> embreeObjects;  // what each of `embree` is
  float scale = 0.0f;

  bool equals(const std::vector<SceneObject>& other) const {
    if (other.size() != objects.size()) return false;
    for (size_t i = 0; i < other.size(); ++i)
      if (!other[i].mesh || !(*other[i].mesh == *objects[i].mesh) || !(other[i].material == objects[i].material) ||
          other[i].objectId != objects[i].objectId)
        return false;
    return true;
  }
};

}  // namespace

struct EmbreeScene::Impl {
  EmbreeErrors errors;  // the device's error callback holds its address
  DevicePtr device{nullptr, &rtcReleaseDevice};
  StaticMeshes statics;
  ScenePtr scene{nullptr, &rtcReleaseScene};  // the frame's
  std::vector<Geometry> geometries;           // the frame's, by geomID
  bool clipOn = false;
  Vector3f clipPoint = Vector3f::Zero(), clipNormal = Vector3f::UnitY();  // unit normal
  float epsilon = 1e-4f;
  int staticBuilds = 0;

  void throwIfError(const char* what) {
    const RTCError code = rtcGetDeviceError(device.get());
    std::lock_guard lock(errors.mutex);
    if (code != RTC_ERROR_NONE || !errors.first.empty())
      throw std::runtime_error(std::string("Embree: ") + what + " failed: " +
                               (errors.first.empty() ? "error " + std::to_string(static_cast<int>(code)) : errors.first));
  }

  StaticMeshes makeStatic(const std::vector<SceneObject>& input) {
    StaticMeshes built;
    for (size_t i = 0; i < input.size(); ++i) {
      const std::string name = "static mesh " + std::to_string(i);
      if (!input[i].mesh) throw std::invalid_argument(name + " has no mesh");
      checkMaterial(input[i].material, name);
      if (!input[i].mesh->triangles.empty()) checkMesh(*input[i].mesh, name);
      built.meshes.push_back(std::make_unique<TriangleMesh>(*input[i].mesh));
      built.objects.push_back({built.meshes.back().get(), input[i].material, input[i].objectId});
    }
    for (const SceneObject& object : built.objects) {
      if (object.mesh->triangles.empty()) continue;  // nothing to hit
      built.embree.push_back(meshGeometry(device.get(), *object.mesh));
      built.embreeObjects.push_back(&object);
      built.scale = std::max(built.scale, largestCoordinate(object.mesh->positions));
    }
    throwIfError("static geometry");
    return built;
  }
};

EmbreeScene::EmbreeScene() : impl_(std::make_unique<Impl>()) {
  impl_->device = newDevice();
  rtcSetDeviceErrorFunction(impl_->device.get(), onEmbreeError, &impl_->errors);
}

EmbreeScene::~EmbreeScene() = default;

void EmbreeScene::update(const RenderScene& scene) {
  Impl& d = *impl_;
  {
    std::lock_guard lock(d.errors.mutex);
    d.errors.first.clear();
  }
  rtcGetDeviceError(d.device.get());  // clears the device's error code
  if (!d.statics.equals(scene.staticMeshes) || d.staticBuilds == 0) {
    d.scene.reset();  // holds the old static geometries
    d.geometries.clear();
    d.statics = d.makeStatic(scene.staticMeshes);
    ++d.staticBuilds;
  }
  // Scene scale for the self-intersection offset: largest coordinate magnitude in view.
  float scale = std::max({scene.camera.position.cwiseAbs().maxCoeff(),
                          scene.ground.enabled ? scene.ground.point.cwiseAbs().maxCoeff() : 0.0f, d.statics.scale});
  ScenePtr top(rtcNewScene(d.device.get()), &rtcReleaseScene);
  std::vector<Geometry> geometries;
  RTCDevice device = d.device.get();
  for (size_t i = 0; i < d.statics.embree.size(); ++i) {
    rtcAttachGeometryByID(top.get(), d.statics.embree[i].get(), unsigned(geometries.size()));
    geometries.push_back({d.statics.embreeObjects[i], nullptr, nullptr, false, {}, nullptr});
  }
  for (size_t i = 0; i < scene.meshes.size(); ++i) {
    const std::string name = "mesh " + std::to_string(i);
    if (!scene.meshes[i].mesh) throw std::invalid_argument(name + " has no mesh");
    checkMaterial(scene.meshes[i].material, name);
    if (scene.meshes[i].mesh->triangles.empty()) continue;  // nothing to hit
    checkMesh(*scene.meshes[i].mesh, name);
    rtcAttachGeometryByID(top.get(), meshGeometry(device, *scene.meshes[i].mesh).get(), unsigned(geometries.size()));
    geometries.push_back({&scene.meshes[i], nullptr, nullptr, false, {}, nullptr});
    scale = std::max(scale, largestCoordinate(scene.meshes[i].mesh->positions));
  }
  for (size_t i = 0; i < scene.spheres.size(); ++i) {
    const SphereSet& set = scene.spheres[i];
    const std::string name = "sphere set " + std::to_string(i);
    checkMaterial(set.material, name);
    if (set.centres.empty()) continue;
    if (!(set.radius > 0.0f)) throw std::invalid_argument(name + ": radius must be > 0");
    if (!set.colours.empty() && set.colours.size() != set.centres.size())
      throw std::invalid_argument(name + ": colours must be empty or one per centre");
    addSpheres(device, top.get(), set, unsigned(geometries.size()));
    geometries.push_back({nullptr, &set, nullptr, false, {}, nullptr});
    scale = std::max(scale, largestCoordinate(set.centres));
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
    const auto curveID = unsigned(geometries.size());
    addCurves(device, top.get(), set, curveID, curveID + 1, curves.primitives, caps.primitives, *caps.capPlanes);
    geometries.push_back(std::move(curves));
    geometries.push_back(std::move(caps));
    for (const Tube& tube : set.tubes) scale = std::max(scale, largestCoordinate(tube.points));
  }
  rtcSetSceneFlags(top.get(), RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION);  // crossings()
  rtcSetSceneBuildQuality(top.get(), RTC_BUILD_QUALITY_HIGH);
  rtcCommitScene(top.get());
  d.throwIfError("scene build");
  d.scene = std::move(top);
  d.geometries = std::move(geometries);
  d.clipOn = scene.clip.enabled;
  if (d.clipOn) {
    d.clipPoint = scene.clip.point;
    d.clipNormal = scene.clip.normal.normalized();
  }
  d.epsilon = 1e-4f * std::max(1.0f, scale);
}

bool EmbreeScene::intersect(const Vector3f& origin, const Vector3f& direction, float tnear, float tfar,
                            RayCounters& counters, EmbreeHit& out) const {
  const Impl& d = *impl_;
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  for (int skip = 0; skip <= kMaxClipSkips; ++skip) {
    RTCRayHit rh{};
    rh.ray.org_x = origin.x(), rh.ray.org_y = origin.y(), rh.ray.org_z = origin.z();
    rh.ray.dir_x = direction.x(), rh.ray.dir_y = direction.y(), rh.ray.dir_z = direction.z();
    rh.ray.tnear = tnear;
    rh.ray.tfar = tfar;
    rh.ray.mask = 0xFFFFFFFFu;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(d.scene.get(), &context, &rh);
    ++counters.total;
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;
    if (!(d.clipOn && (origin + rh.ray.tfar * direction - d.clipPoint).dot(d.clipNormal) > 0.0f)) {
      out.t = rh.ray.tfar;
      out.geomID = rh.hit.geomID;
      out.primID = rh.hit.primID;
      out.u = rh.hit.u;
      out.v = rh.hit.v;
      out.ng = {rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z};
      return true;
    }
    tnear = rh.ray.tfar + d.epsilon;
  }
  return false;
}

bool EmbreeScene::occluded(const Vector3f& origin, const Vector3f& direction, float tfar,
                           RayCounters& counters) const {
  const Impl& d = *impl_;
  if (d.clipOn) {
    EmbreeHit hit;
    return intersect(origin, direction, 0.0f, tfar, counters, hit);
  }
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRay ray = segment(origin, direction, tfar);
  rtcOccluded1(d.scene.get(), &context, &ray);
  ++counters.total;
  return ray.tfar == -kInfinity;  // Embree marks a hit by setting tfar to -inf
}

Hit EmbreeScene::surface(const Vector3f& origin, const Vector3f& direction, const EmbreeHit& e) const {
  const Impl& d = *impl_;
  Hit hit;
  hit.kind = Hit::Surface;
  hit.t = e.t;
  hit.point = origin + e.t * direction;
  const Geometry& g = d.geometries[e.geomID];
  const unsigned primID = e.primID;
  hitNormals(g, primID, e.u, e.v, hit.point, e.ng, direction, hit.ng, hit.ns);
  hit.material = &geometryMaterial(g);
  if (g.curves) {
    const Tube& tube = g.curves->tubes[g.primitives[primID].first];
    hit.albedo = checkerAlbedo(g.curves->material, g.curves->material.albedo, hit.point);
    hit.objectId = tube.objectId != 0 ? tube.objectId : g.curves->objectId;
  } else if (g.mesh) {
    hit.albedo = checkerAlbedo(g.mesh->material, g.mesh->material.albedo, hit.point);
    hit.objectId = g.mesh->objectId;
  } else {
    const SphereSet& set = *g.spheres;
    hit.albedo = set.colours.empty() ? set.material.albedo : set.colours[primID];
    hit.objectId = set.objectId;
  }
  return hit;
}

int EmbreeScene::crossings(const Vector3f& origin, const Vector3f& direction, float tfar, RayCounters& counters,
                           Crossing* out, int capacity) const {
  const Impl& d = *impl_;
  CrossingQuery query;
  rtcInitIntersectContext(&query.context);
  query.context.filter = crossingFilter;
  query.geometries = &d.geometries;
  query.clipOn = d.clipOn;
  query.clipPoint = d.clipPoint;
  query.clipNormal = d.clipNormal;
  query.epsilon = d.epsilon;
  query.origin = origin;
  query.direction = direction;
  query.out = out;
  query.capacity = capacity;
  RTCRay ray = segment(origin, direction, tfar);
  rtcOccluded1(d.scene.get(), &query.context, &ray);
  ++counters.total;
  return ray.tfar == -kInfinity ? -1 : query.count;
}

float EmbreeScene::epsilon() const { return impl_->epsilon; }

void EmbreeScene::throwIfError(const char* what) const { impl_->throwIfError(what); }

int EmbreeScene::staticBuilds() const { return impl_->staticBuilds; }

std::string embreeVersion() {
  DevicePtr device = newDevice();
  const auto version = rtcGetDeviceProperty(device.get(), RTC_DEVICE_PROPERTY_VERSION);  // e.g. 31305
  return std::to_string(version / 10000) + "." + std::to_string(version / 100 % 100) + "." +
         std::to_string(version % 100);
}

}  // namespace kurage::render
