// Embree 3 ray tracer; see tracer.h.
//
// Per frame: one RTCDevice and RTCScene holding one triangle geometry per SceneObject (buffers
// copied into Embree-allocated, correctly padded storage). The ground is an analytic plane
// intersected here, not in Embree, so it is truly infinite; it receives shadows from meshes
// but casts none. Shading is Lambert:
//   albedo * (radiance * max(0, n . -l) * visibility + ambient * (skyZenith + skyHorizon) / 2)
// i.e. the ambient term is uniform, using the mean sky colour.
// Pixel sample positions are a Hammersley set (shifted by half a stratum) indexed by sample
// number, so every pixel is a fixed function of the scene and the image does not depend on
// tiling or thread count.
#include "render/tracer.h"

#include <embree3/rtcore.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <Eigen/Geometry>

#include <algorithm>
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

// Copies one mesh into a committed Embree triangle geometry attached to `scene`.
void addMesh(RTCDevice device, RTCScene scene, const TriangleMesh& mesh, size_t objectIndex) {
  const std::string name = "scene object " + std::to_string(objectIndex);
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
  rtcCommitGeometry(geometry);
  rtcAttachGeometryByID(scene, geometry, static_cast<unsigned>(objectIndex));  // geomID = object index
  rtcReleaseGeometry(geometry);
}

// Van der Corput radical inverse in base 2.
float radicalInverse2(unsigned bits) {
  bits = (bits << 16u) | (bits >> 16u);
  bits = ((bits & 0x55555555u) << 1u) | ((bits & 0xAAAAAAAAu) >> 1u);
  bits = ((bits & 0x33333333u) << 2u) | ((bits & 0xCCCCCCCCu) >> 2u);
  bits = ((bits & 0x0F0F0F0Fu) << 4u) | ((bits & 0xF0F0F0F0u) >> 4u);
  bits = ((bits & 0x00FF00FFu) << 8u) | ((bits & 0xFF00FF00u) >> 8u);
  return static_cast<float>(bits) * 0x1p-32f;
}

// Sub-pixel position of sample s of n in [0,1)^2: Hammersley point shifted by half a stratum
// (n = 1 gives the pixel centre, n = 4 a rotated-grid pattern).
Vector2f samplePosition(int s, int n) {
  const float half = 0.5f / static_cast<float>(n);
  const float y = radicalInverse2(static_cast<unsigned>(s)) + half;
  return {(static_cast<float>(s) + 0.5f) / static_cast<float>(n), y >= 1.0f ? y - 1.0f : y};
}

// Everything a worker thread needs to shade a ray; read-only during rendering.
struct Frame {
  RTCScene scene = nullptr;
  const std::vector<SceneObject>* objects = nullptr;
  const Ground* ground = nullptr;
  const RenderSettings* settings = nullptr;
  Vector3f toLight;        // unit, towards the light
  Vector3f radiance;
  Vector3f skyUp;          // unit camera up, for the sky gradient
  Vector3f ambient;        // ambient * mean sky colour
  Vector3f groundNormal;   // unit
  Vector3f groundU, groundV;  // unit, spanning the ground plane (checker axes)
  float epsilon = 1e-4f;   // ray offset against self-intersection, metres
};

Vector3f skyColour(const Frame& f, const Vector3f& direction) {
  const float t = std::clamp(direction.dot(f.skyUp), 0.0f, 1.0f);  // 0 at horizon, 1 at zenith
  return (1.0f - t) * f.settings->skyHorizon + t * f.settings->skyZenith;
}

// Whether anything in the Embree scene blocks the light from `origin`.
bool occluded(const Frame& f, const Vector3f& origin, RTCIntersectContext& context) {
  RTCRay ray{};
  ray.org_x = origin.x(), ray.org_y = origin.y(), ray.org_z = origin.z();
  ray.dir_x = f.toLight.x(), ray.dir_y = f.toLight.y(), ray.dir_z = f.toLight.z();
  ray.tnear = f.epsilon;
  ray.tfar = kInfinity;
  ray.mask = 0xFFFFFFFFu;
  rtcOccluded1(f.scene, &context, &ray);
  return ray.tfar == -kInfinity;  // Embree marks a hit by setting tfar to -inf
}

// Lambert shading at `point` with unit normal `normal` (facing the viewer) and geometric
// normal `geometricNormal` (facing the viewer, used to offset the shadow ray).
Vector3f shade(const Frame& f, const Vector3f& point, const Vector3f& normal, const Vector3f& geometricNormal,
               const Vector3f& albedo, RTCIntersectContext& context) {
  Vector3f light = f.ambient;
  const float cosine = normal.dot(f.toLight);
  if (cosine > 0.0f && !occluded(f, point + f.epsilon * geometricNormal, context))
    light += cosine * f.radiance;
  return albedo.cwiseProduct(light);
}

Vector3f groundAlbedo(const Frame& f, const Vector3f& point) {
  const Ground& g = *f.ground;
  if (g.checkerSize <= 0.0f) return g.albedoA;
  const Vector3f offset = point - g.point;
  const double cells = std::floor(offset.dot(f.groundU) / g.checkerSize) + std::floor(offset.dot(f.groundV) / g.checkerSize);
  return std::fmod(cells, 2.0) == 0.0 ? g.albedoA : g.albedoB;
}

Vector3f trace(const Frame& f, const Vector3f& origin, const Vector3f& direction, RTCIntersectContext& context) {
  RTCRayHit rh{};
  rh.ray.org_x = origin.x(), rh.ray.org_y = origin.y(), rh.ray.org_z = origin.z();
  rh.ray.dir_x = direction.x(), rh.ray.dir_y = direction.y(), rh.ray.dir_z = direction.z();
  rh.ray.tnear = 0.0f;
  rh.ray.tfar = kInfinity;
  rh.ray.mask = 0xFFFFFFFFu;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(f.scene, &context, &rh);

  float groundT = kInfinity;
  if (f.ground->enabled) {
    const float denominator = direction.dot(f.groundNormal);
    if (denominator != 0.0f) {
      const float t = (f.ground->point - origin).dot(f.groundNormal) / denominator;
      if (t > 0.0f) groundT = t;
    }
  }

  if (rh.hit.geomID != RTC_INVALID_GEOMETRY_ID && rh.ray.tfar <= groundT) {
    const SceneObject& object = (*f.objects)[rh.hit.geomID];
    const TriangleMesh& mesh = *object.mesh;
    const Vector3f point = origin + rh.ray.tfar * direction;
    Vector3f geometric = Vector3f(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z).normalized();
    if (geometric.dot(direction) > 0.0f) geometric = -geometric;
    Vector3f normal = geometric;
    if (!mesh.normals.empty()) {  // smooth shading: barycentric interpolation of vertex normals
      const Eigen::Vector3i& tri = mesh.triangles[rh.hit.primID];
      const float u = rh.hit.u, v = rh.hit.v;
      const Vector3f interpolated =
          (1.0f - u - v) * mesh.normals[tri[0]] + u * mesh.normals[tri[1]] + v * mesh.normals[tri[2]];
      if (interpolated.squaredNorm() > 0.0f) {
        normal = interpolated.normalized();
        if (normal.dot(direction) > 0.0f) normal = -normal;
      }
    }
    return shade(f, point, normal, geometric, object.material.albedo, context);
  }
  if (groundT < kInfinity) {
    const Vector3f point = origin + groundT * direction;
    const Vector3f normal = direction.dot(f.groundNormal) < 0.0f ? f.groundNormal : Vector3f(-f.groundNormal);
    return shade(f, point, normal, normal, groundAlbedo(f, point), context);
  }
  return skyColour(f, direction);
}

}  // namespace

Image renderFrame(const std::vector<SceneObject>& objects, const Camera& camera, const DirectionalLight& light,
                  const Ground& ground, const RenderSettings& settings) {
  if (settings.width <= 0 || settings.height <= 0 || settings.samplesPerPixel <= 0)
    throw std::invalid_argument("renderFrame: width, height and samplesPerPixel must be positive");
  if (!(settings.ambient >= 0.0f)) throw std::invalid_argument("renderFrame: ambient must be >= 0");
  if (!(camera.verticalFovDegrees > 0.0f && camera.verticalFovDegrees < 180.0f))
    throw std::invalid_argument("renderFrame: verticalFovDegrees must be in (0, 180)");
  if (light.direction.squaredNorm() == 0.0f) throw std::invalid_argument("renderFrame: zero light direction");
  if (ground.enabled && ground.normal.squaredNorm() == 0.0f)
    throw std::invalid_argument("renderFrame: zero ground normal");

  // Camera basis (look-at); up must not be parallel to the viewing direction.
  const Vector3f forward = (camera.lookAt - camera.position).normalized();
  const Vector3f right = forward.cross(camera.up).normalized();
  if (!right.allFinite() || camera.up.squaredNorm() == 0.0f)
    throw std::invalid_argument("renderFrame: camera position, lookAt and up are degenerate");
  const Vector3f trueUp = right.cross(forward);
  const float tanHalfFov =
      std::tan(0.5f * camera.verticalFovDegrees * std::numbers::pi_v<float> / 180.0f);
  const float aspect = static_cast<float>(settings.width) / static_cast<float>(settings.height);

  EmbreeErrors errors;
  DevicePtr device = newDevice();
  rtcSetDeviceErrorFunction(device.get(), onEmbreeError, &errors);
  ScenePtr scene(rtcNewScene(device.get()), &rtcReleaseScene);
  // Scene scale for the self-intersection offset: largest coordinate magnitude in view.
  float scale = std::max(camera.position.cwiseAbs().maxCoeff(), ground.enabled ? ground.point.cwiseAbs().maxCoeff() : 0.0f);
  for (size_t i = 0; i < objects.size(); ++i) {
    if (!objects[i].mesh) throw std::invalid_argument("renderFrame: scene object " + std::to_string(i) + " has no mesh");
    if (objects[i].mesh->triangles.empty()) continue;  // nothing to hit
    addMesh(device.get(), scene.get(), *objects[i].mesh, i);
    for (const Vector3f& p : objects[i].mesh->positions) scale = std::max(scale, p.cwiseAbs().maxCoeff());
  }
  rtcCommitScene(scene.get());
  throwIfError(device.get(), errors, "scene build");

  Frame frame;
  frame.scene = scene.get();
  frame.objects = &objects;
  frame.ground = &ground;
  frame.settings = &settings;
  frame.toLight = -light.direction.normalized();
  frame.radiance = light.radiance;
  frame.skyUp = camera.up.normalized();
  frame.ambient = settings.ambient * 0.5f * (settings.skyZenith + settings.skyHorizon);
  frame.epsilon = 1e-4f * std::max(1.0f, scale);
  if (ground.enabled) {
    frame.groundNormal = ground.normal.normalized();
    const Vector3f axis = std::abs(frame.groundNormal.x()) < 0.9f ? Vector3f::UnitX() : Vector3f::UnitY();
    frame.groundU = (axis - frame.groundNormal.dot(axis) * frame.groundNormal).normalized();
    frame.groundV = frame.groundNormal.cross(frame.groundU);
  }

  Image image(settings.width, settings.height);
  const int tilesX = (settings.width + kTileSize - 1) / kTileSize;
  const int tilesY = (settings.height + kTileSize - 1) / kTileSize;
  const int n = settings.samplesPerPixel;
  tbb::parallel_for(tbb::blocked_range<int>(0, tilesX * tilesY), [&](const tbb::blocked_range<int>& tiles) {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    for (int tile = tiles.begin(); tile != tiles.end(); ++tile) {
      const int x0 = (tile % tilesX) * kTileSize, y0 = (tile / tilesX) * kTileSize;
      for (int y = y0; y < std::min(y0 + kTileSize, settings.height); ++y)
        for (int x = x0; x < std::min(x0 + kTileSize, settings.width); ++x) {
          Vector3f sum = Vector3f::Zero();
          for (int s = 0; s < n; ++s) {
            const Vector2f offset = samplePosition(s, n);
            // Image plane at distance 1: x in [-aspect, aspect] * tan, y in [-1, 1] * tan, row 0 on top.
            const float px = (2.0f * (static_cast<float>(x) + offset.x()) / static_cast<float>(settings.width) - 1.0f) * aspect * tanHalfFov;
            const float py = (1.0f - 2.0f * (static_cast<float>(y) + offset.y()) / static_cast<float>(settings.height)) * tanHalfFov;
            const Vector3f direction = (forward + px * right + py * trueUp).normalized();
            sum += trace(frame, camera.position, direction, context);
          }
          const Vector3f colour = sum / static_cast<float>(n);
          image.at(x, y) = Eigen::Vector4f(colour.x(), colour.y(), colour.z(), 1.0f);
        }
    }
  });
  throwIfError(device.get(), errors, "rendering");
  return image;
}

std::string embreeVersion() {
  DevicePtr device = newDevice();
  const auto version = rtcGetDeviceProperty(device.get(), RTC_DEVICE_PROPERTY_VERSION);  // e.g. 31305
  return std::to_string(version / 10000) + "." + std::to_string(version / 100 % 100) + "." +
         std::to_string(version % 100);
}

}  // namespace kurage::render
