// See frame_scene.h.
#include "render/frame_scene.h"

#include "render/materials.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace kurage::render {

namespace {
using Eigen::Vector3f;
constexpr float kInfinity = std::numeric_limits<float>::infinity();
constexpr int kMaxShadowCrossings = 16;  // dielectric surfaces a shadow ray may pass

Vector3f groundAlbedo(const FrameScene& f, const Vector3f& point) {
  const Ground& g = f.input.ground;
  if (g.checkerSize <= 0.0f) return g.albedoA;
  const Vector3f offset = point - g.point;
  const double cells = std::floor(offset.dot(f.groundU) / g.checkerSize) + std::floor(offset.dot(f.groundV) / g.checkerSize);
  return std::fmod(std::abs(cells), 2.0) == 0.0 ? g.albedoA : g.albedoB;
}
}  // namespace

FrameScene::FrameScene(const RenderScene& scene, const EmbreeScene& embree, const EnvironmentSampler& sampler,
                       bool transmissive)
    : input(scene), geometry(embree), environment(sampler), transmissiveShadows(transmissive),
      epsilon(embree.epsilon()) {
  toSun = -scene.sun.direction.normalized();
  const float sunRadius = 0.5f * scene.sun.angularDiameterDegrees * std::numbers::pi_v<float> / 180.0f;
  sunCosMax = std::cos(sunRadius);
  const float sunSolidAngle = 2.0f * std::numbers::pi_v<float> * (1.0f - sunCosMax);
  sunRadiance = sunSolidAngle > 0.0f ? Vector3f(scene.sun.irradiance / sunSolidAngle) : Vector3f::Zero();
  sunOn = scene.sun.irradiance.maxCoeff() > 0.0f;
  if (scene.ground.enabled) {
    groundNormal = scene.ground.normal.normalized();
    const Vector3f axis = std::abs(groundNormal.x()) < 0.9f ? Vector3f::UnitX() : Vector3f::UnitY();
    groundU = (axis - groundNormal.dot(axis) * groundNormal).normalized();
    groundV = groundNormal.cross(groundU);
  }
}

Hit FrameScene::intersect(const Vector3f& origin, const Vector3f& direction, RayCounters& counters) const {
  Hit hit;
  EmbreeHit e;
  if (geometry.intersect(origin, direction, 0.0f, kInfinity, counters, e)) hit = geometry.surface(origin, direction, e);
  const Ground& ground = input.ground;
  if (ground.enabled) {
    const float denominator = direction.dot(groundNormal);
    if (denominator != 0.0f) {
      const float tg = (ground.point - origin).dot(groundNormal) / denominator;
      if (tg > 0.0f && tg < hit.t) {
        hit.kind = Hit::Ground;
        hit.t = tg;
        hit.point = origin + tg * direction;
        hit.ng = hit.ns = groundNormal;
        hit.material = nullptr;
        hit.albedo = groundAlbedo(*this, hit.point);
        hit.objectId = kObjectGround;
      }
    }
  }
  const std::vector<RectLight>& lights = input.rectLights;
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

Vector3f FrameScene::transmittance(const Vector3f& origin, const Vector3f& direction, float tfar,
                                   RayCounters& counters) const {
  if (!transmissiveShadows)
    return geometry.occluded(origin, direction, tfar, counters) ? Vector3f::Zero() : Vector3f::Ones();
  Crossing crossings[kMaxShadowCrossings];
  const int count = geometry.crossings(origin, direction, tfar, counters, crossings, kMaxShadowCrossings);
  if (count < 0) return Vector3f::Zero();
  std::sort(crossings, crossings + count, [](const Crossing& a, const Crossing& b) { return a.t < b.t; });
  Vector3f through = Vector3f::Ones();
  float etendue = 1.0f;  // the product of ior^2 entered and 1/ior^2 left
  float previous = 0.0f;  // distance of the last crossing
  for (int k = 0; k < count; ++k) {
    const Crossing& c = crossings[k];
    const Material& m = *c.material;
    const float cosine = direction.dot(c.ng);
    const bool leaving = cosine > 0.0f;  // the segment just travelled was inside
    through *= 1.0f - fresnelDielectric(std::abs(cosine), 1.0f, m.ior);
    if (leaving) through = through.cwiseProduct((-m.absorption * (c.t - previous)).array().exp().matrix());
    etendue *= leaving ? 1.0f / (m.ior * m.ior) : m.ior * m.ior;
    previous = c.t;
  }
  return through * etendue;
}

Vector3f FrameScene::filteredAlbedo(const Hit& hit, const Vector3f& direction, float width) const {
  const Ground& g = input.ground;
  const bool ground = hit.kind == Hit::Ground;
  if (!(width > 0.0f) || (ground ? !(g.checkerSize > 0.0f) : !(hit.material && hit.material->checkerSize > 0.0f)))
    return hit.albedo;
  const Vector3f& n = hit.ng;
  const float cosine = std::max(std::abs(direction.dot(n)), 1e-4f);
  Vector3f across = direction.cross(n);
  if (across.squaredNorm() < 1e-12f) across = n.unitOrthogonal();
  across.normalize();
  const Vector3f a1 = width * across, a2 = (width / cosine) * n.cross(across);
  if (!ground) {
    const Vector3f box = (a1.cwiseAbs2() + a2.cwiseAbs2()).cwiseSqrt();
    return checkerAlbedoFiltered(*hit.material, hit.material->albedo, hit.point, box);
  }
  const Vector3f offset = hit.point - g.point;
  double parity = 1.0;
  for (const Vector3f& axis : {groundU, groundV}) {
    const double centre = double(offset.dot(axis)) / g.checkerSize;
    const double half = 0.5 * std::hypot(double(a1.dot(axis)), double(a2.dot(axis))) / g.checkerSize;
    parity *= checkerWaveMean(centre - half, centre + half);
  }
  return checkerBlend(parity, g.albedoA, g.albedoB);
}

Vector3f FrameScene::meanAlbedo(const Hit& hit) const {
  const Ground& g = input.ground;
  if (hit.kind == Hit::Ground) return g.checkerSize > 0.0f ? checkerBlend(0.0, g.albedoA, g.albedoB) : hit.albedo;
  const Material* m = hit.material;
  return m && m->checkerSize > 0.0f ? checkerBlend(0.0, m->albedo, m->albedoB) : hit.albedo;
}

bool FrameScene::groundBlocks(const Vector3f& origin, const Vector3f& direction) const {
  if (!input.ground.enabled) return false;
  const float denominator = direction.dot(groundNormal);
  return denominator != 0.0f && (input.ground.point - origin).dot(groundNormal) / denominator > 0.0f;
}

}  // namespace kurage::render
