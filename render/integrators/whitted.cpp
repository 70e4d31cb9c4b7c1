// The Whitted integrator (RenderSettings::integrator "whitted"): deterministic ray tracing in the
// manner of Whitted (1980), "An improved illumination model for shaded display", and POV-Ray.
//
// At dielectric surfaces both the Fresnel-reflected and the refracted ray are followed (a tree,
// cut at maxDepth and where a branch's weight, the product of its Fresnel and mirror factors,
// falls below 1e-3); mirrors reflect; diffuse surfaces take only direct light:
//   sun        along its centre direction (hard shadows), irradiance E f cos
//   area light at the centres of a lightSamples x lightSamples grid on it, each
//              L cos_light A / (d^2 grid^2) f cos
//   sky        along skyDirections fixed cosine-distributed directions about the shading normal
//              (each with its shadow ray), (albedo / K) sum L T over K directions, the cosine
//              weighting cancelling the cosine (sum L T / K estimates E / pi)
// The sky directions differ from sample to sample of a pixel: sample s of S takes points s,
// s + S, ... of one Hammersley set of skyDirections x S points, the same at every pixel, so the
// pixel averages skyDirections x S directions and the sky's shadows are not skyDirections hard
// copies. S is samplesPerPixel, or, for the first pass of edge-adaptive anti-aliasing
// (renderer.h), its minSamples: each count has its own set. With the sky filter
// (SkyFilterSettings, renderer.h) the pixel at (x mod N, y mod N) = (a, b) of a tile of N x N turns
// the set by (du, dv) = (((c + 1/2) / N - 1/2) / P, (b + c / N) / N), c = (a + b) mod N (mod 1 in v;
// P the set's size): each of the set's P strata in the first coordinate is split in N, each part
// holding N points evenly spaced in the second, so the tile's N^2 sets together are one stratified
// set of N^2 P points while each pixel keeps a stratified set of its own (interleaved sampling,
// Keller & Heidrich 2001); every row and column of the tile holds each part c once (a Latin
// square), so a window cut at an edge still sees every elevation band equally. The sky
// term of the primary diffuse vertex is then returned apart (PathFeatures::sky) for the render
// loop's filter. Shadow rays follow RenderSettings::transmissiveShadows. Translucent
// bodies are shaded as diffuse with albedo tint^2 (1 - F) (light scattered in and out once) plus
// the Fresnel reflection. No indirect diffuse light, no caustics.
//
// Secondary light is clamped (clampSecondary = c > 0): what the rays leaving a camera ray's first
// hit add to a sample (depth >= 1: reflections, refractions and all they see) is clamped to c in
// each channel before the pixel's mean, in the manner of Cycles' "clamp indirect" (per channel, not
// scaled: at c = 1 a region overexposed in every sample shows as before, the PNG clamps alike).
// The sun's disc seen along one sample's mirror branch (radiance E / Omega, about 4e4 for 0.53
// degrees) then lightens a pixel of S samples by at most c / S instead of saturating it, and a
// glint that covers the pixel still reaches c. The camera's own rays (the sun, sky, lights and
// the first hit's direct light) are never clamped. Biased: a sample's secondary light above c is
// lost, in every output (the EXR too).
//
// Textures (filterTextures): every ray carries a cone (Amanatides 1984, "Ray tracing with cones";
// Akenine-Moller et al. 2021, JCGT 10(1)): width w = w0 + spread t, starting at the pinhole with
// w0 = 0 and spread = p cos^1.5(theta), p = 2 tan(fov/2) / height the angle of a pixel on the
// axis, theta the ray's angle to the axis (a pixel subtends p cos^2 radially and p cos
// tangentially; the geometric mean). Every sample filters over the whole pixel's footprint, not
// its 1/S share: the fixed sub-pixel points are no grid whose shares would tile the pixel, and on
// a plane the whole footprint gives the pixel's exact mean at any S (at an object's outline the
// texture is averaged a little past it). Reflection keeps the spread; refraction scales it by
// eta_i / eta_t (Snell's law at normal incidence); surface curvature is ignored. A checker is
// averaged over the cone's footprint in closed form (FrameScene::filteredAlbedo), so a far
// checker ground converges to its mean where point samples alias. The sun, lights and sky are
// not filtered. Where the render loop asks for features (edge-adaptive anti-aliasing), each ray
// returns alongside the radiance its edge value (PathFeatures::edge, what it compares): the same
// tree with every filtered checker's albedo at the mean of its two colours, so a checker's edges,
// which the filter handles, do not count.
//
// Camera samples: samplesPerPixel fixed sub-pixel positions of a Hammersley set shifted half a
// stratum in ((s + 1/2)/n, frac(radicalInverse2(s) + 1/2n)), the lens point the same two numbers
// swapped. The image depends on neither the seed nor the thread count, and has no noise; the
// random numbers go unused.
#include "render/integrators/integrator.h"
#include "render/renderer.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <utility>
#include <vector>

namespace kurage::render {
namespace {

using Eigen::Vector3f;

constexpr float kInfinity = std::numeric_limits<float>::infinity();
constexpr float kWhittedCutoff = 1e-3f;  // branches whose weight falls below this are dropped
const Material kGroundMaterial{};

// v with every channel at most `most` (0: v as it is).
Vector3f clampedTo(const Vector3f& v, float most) { return most > 0.0f ? Vector3f(v.cwiseMin(most)) : v; }

class WhittedIntegrator final : public Integrator {
public:
  WhittedIntegrator(const FrameScene& scene, const RenderSettings& settings)
      : f_(scene), settings_(settings) {
    const Camera& camera = scene.input.camera;
    forward_ = (camera.lookAt - camera.position).normalized();
    pixelAngle_ = settings.whitted.filterTextures
                      ? 2.0f * std::tan(0.5f * camera.verticalFovDegrees * std::numbers::pi_v<float> / 180.0f) /
                            float(std::max(1, settings.height))
                      : 0.0f;
    if (settings.whitted.skyFilter.enabled) tile_ = std::max(1, settings.whitted.skyFilter.tile);
    addSkySet(std::max(1, settings.samplesPerPixel));
    const EdgeAdaptiveSettings& adaptive = settings.whitted.adaptive;
    if (adaptive.enabled && adaptive.minSamples < settings.samplesPerPixel) addSkySet(adaptive.minSamples);
  }

  bool noisy() const override { return false; }

  CameraSample cameraSample(uint32_t, int s, int n, PixelSampler&) const override {
    const float sx = (float(s) + 0.5f) / float(n);
    float sy = radicalInverse2(uint32_t(s)) + 0.5f / float(n);
    sy -= std::floor(sy);
    return {{sx, sy}, {sy, sx}};
  }

  Vector3f radiance(const Vector3f& origin, const Vector3f& direction, uint32_t pixel, int s, int n, PixelSampler&,
                    RayCounters& counters, bool& hitSomething, PathFeatures* features) const override {
    const float cosine = std::max(0.0f, forward_.dot(direction));
    const Cone cone{0.0f, pixelAngle_ * cosine * std::sqrt(cosine)};
    const SkySet* sky = &skySets_.front();
    for (const SkySet& set : skySets_)
      if (set.samples == n) sky = &set;
    size_t turn = 0;
    if (tile_ > 1) {
      const uint32_t width = uint32_t(std::max(1, settings_.width));
      turn = size_t((pixel % width) % uint32_t(tile_)) * size_t(tile_) + size_t((pixel / width) % uint32_t(tile_));
    }
    const bool edges = features && features->wantEdge;
    const Sample sample{s, &sky->local[turn], sky->samples, edges, tile_ > 1 ? features : nullptr};
    const Traced traced = trace(origin, direction, 0, Vector3f::Zero(), {1.0f, Vector3f::Ones(), 0.0f, true}, cone,
                                sample, counters, &hitSomething);
    if (edges) features->edge = traced.edge;
    return traced.value;
  }

private:
  // A ray's cone: width (metres) at the ray's origin, and its growth per metre (radians).
  struct Cone {
    float width = 0.0f, spread = 0.0f;
  };
  // Fixed points warped to sky directions in the normal's frame (cosineHemisphereLocal),
  // skyDirections x samples of them (one Hammersley set, shifted half a stratum off the pole); sample
  // s of `samples` takes points s, s + samples, ... local[a N + b]: the set turned for the pixel at
  // (a, b) of the sky filter's tile (one set without the filter).
  struct SkySet {
    int samples = 1;
    std::vector<std::vector<Vector3f>> local;
  };
  // Where a branch stands: its weight (the product of its Fresnel and mirror factors, for the
  // cutoff), its throughput from the camera (factors and absorption), its length so far, and whether
  // it is the primary branch (the heavier one at each split).
  struct Branch {
    float weight = 1.0f;
    Vector3f throughput = Vector3f::Ones();
    float distance = 0.0f;
    bool primary = true;
  };
  // A diffuse point's direct light of albedo 1: the sun and area lights, and the sky.
  struct Direct {
    Vector3f lights = Vector3f::Zero(), sky = Vector3f::Zero();
  };
  // A ray's radiance, and the same with every checker's albedo replaced by the mean of its two
  // colours where textures are filtered (what edge-adaptive anti-aliasing compares: the cone
  // filter already averages a checker's edges; geometry, shadows and plain colours remain).
  struct Traced {
    Vector3f value = Vector3f::Zero(), edge = Vector3f::Zero();
  };
  // The camera sample a ray belongs to: its index, its pixel's sky set (of the sample count
  // `samples`), whether its edge value is wanted (Traced::edge stays 0 otherwise), and where the
  // primary diffuse vertex's sky term goes (null: nowhere).
  struct Sample {
    int index = 0;
    const std::vector<Vector3f>* sky = nullptr;
    int samples = 1;
    bool edges = false;
    PathFeatures* primary = nullptr;
  };
  void addSkySet(int samples) {
    SkySet set{samples, {}};
    const int points = settings_.whitted.skyDirections * samples;
    const float n = float(tile_);
    for (int a = 0; a < tile_; ++a)
      for (int b = 0; b < tile_; ++b) {
        const int c = (a + b) % tile_;
        const float du = ((float(c) + 0.5f) / n - 0.5f) / float(points), dv = (float(b) + float(c) / n) / n;
        std::vector<Vector3f>& local = set.local.emplace_back();
        for (int k = 0; k < points; ++k) {
          float v = radicalInverse2(uint32_t(k)) + 0.5f / float(points) + dv;
          v -= std::floor(v);
          local.push_back(cosineHemisphereLocal((float(k) + 0.5f) / float(points) + du, v));
        }
      }
    skySets_.push_back(std::move(set));
  }
  Direct direct(const Hit& hit, const Vector3f& wo, const Sample& sample, RayCounters& counters) const;
  Traced trace(const Vector3f& origin, const Vector3f& direction, int depth, const Vector3f& absorption,
               const Branch& branch, const Cone& cone, const Sample& sample, RayCounters& counters,
               bool* hitSomething) const;

  const FrameScene& f_;
  const RenderSettings& settings_;
  int tile_ = 1;                 // the sky filter's tile (1: no filter)
  std::vector<SkySet> skySets_;  // for samplesPerPixel, then for the adaptive first pass
  Vector3f forward_;         // the camera's viewing direction, unit
  float pixelAngle_ = 0.0f;  // a pixel's cone spread on the axis, radians (0: no filtering)
};

// Direct light at a diffuse point of albedo 1 (the caller multiplies by its albedo), no noise:
// the sun along its centre
// direction, each area light at the centres of an n x n grid, the sky along the fixed
// cosine-distributed directions about the shading normal that belong to the pixel's sample
// `sample` (its SkySet), turned to wo's side.
WhittedIntegrator::Direct WhittedIntegrator::direct(const Hit& hit, const Vector3f& wo, const Sample& sample,
                                                   RayCounters& counters) const {
  const FrameScene& f = f_;
  const bool outside = wo.dot(hit.ng) >= 0.0f;
  const Vector3f g = outside ? hit.ng : Vector3f(-hit.ng);
  Vector3f n = outside ? hit.ns : Vector3f(-hit.ns);
  if (!(wo.dot(n) > 1e-6f)) n = g;
  const float invPi = 1.0f / std::numbers::pi_v<float>;
  const auto fcos = [&](const Vector3f& wi) {
    return wi.dot(g) > 0.0f ? Vector3f::Constant(invPi * std::max(0.0f, wi.dot(n))) : Vector3f::Zero();
  };
  Vector3f sum = Vector3f::Zero();
  if (f.sunOn) {
    const Vector3f c = fcos(f.toSun);
    if (c.maxCoeff() > 0.0f)
      sum += c.cwiseProduct(f.input.sun.irradiance)
                 .cwiseProduct(f.transmittance(f.leave(hit, f.toSun), f.toSun, kInfinity, counters));
  }
  const int grid = settings_.whitted.lightSamples;
  for (const RectLight& l : f.input.rectLights) {
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
        sum += c.cwiseProduct(l.radiance)
                   .cwiseProduct(f.transmittance(f.leave(hit, wi), wi, distance * (1.0f - 1e-4f), counters)) *
               (cosLight * area / (distance2 * float(grid * grid)));
      }
  }
  Vector3f sky = Vector3f::Zero();
  const std::vector<Vector3f>& set = *sample.sky;
  const int samples = sample.samples;
  Vector3f t, b;
  orthonormalBasis(n, t, b);
  for (size_t k = size_t(sample.index % samples); k < set.size(); k += size_t(samples)) {
    const Vector3f wi = fromLocal(set[k], t, b, n);
    if (wi.dot(g) <= 0.0f) continue;
    const Vector3f from = f.leave(hit, wi);
    if (f.groundBlocks(from, wi)) continue;
    sky += environmentRadiance(f.input.environment, wi).cwiseProduct(f.transmittance(from, wi, kInfinity, counters));
  }
  if (!set.empty()) sky *= float(samples) / float(set.size());
  return {sum, sky};
}

// Radiance along a ray of the branch `branch`; `absorption` is the medium's coefficient (0: air).
WhittedIntegrator::Traced WhittedIntegrator::trace(const Vector3f& origin, const Vector3f& direction, int depth,
                                                  const Vector3f& absorption, const Branch& branch, const Cone& cone,
                                                  const Sample& sample, RayCounters& counters,
                                                  bool* hitSomething) const {
  const FrameScene& f = f_;
  const Hit hit = f.intersect(origin, direction, counters);
  if (hitSomething) *hitSomething = hit.kind != Hit::None;
  if (hit.kind == Hit::None) {
    if (depth == 0 && settings_.transparentBackground) return {};
    Vector3f l = environmentRadiance(f.input.environment, direction);
    if (f.sunOn && f.sunCosMax < 1.0f && direction.dot(f.toSun) >= f.sunCosMax) l += f.sunRadiance;
    return {l, l};
  }
  const Vector3f attenuation =
      absorption.maxCoeff() > 0.0f ? Vector3f((-absorption * hit.t).array().exp().matrix()) : Vector3f::Ones();
  if (hit.kind == Hit::Light) {
    if (!(direction.dot(hit.ng) < 0.0f)) return {};
    const Vector3f l = attenuation.cwiseProduct(f.input.rectLights[size_t(hit.light)].radiance);
    return {l, l};
  }
  if (depth >= settings_.maxDepth) return {};
  const Material& material = hit.material ? *hit.material : kGroundMaterial;
  const Vector3f wo = -direction;
  const float width = cone.width + cone.spread * hit.t;
  const bool filtered = cone.spread > 0.0f;
  const Vector3f albedo = filtered ? f.filteredAlbedo(hit, direction, width) : hit.albedo;
  const Vector3f edgeAlbedo = !sample.edges ? Vector3f::Zero() : filtered ? f.meanAlbedo(hit) : albedo;
  Traced radiance, secondary;  // secondary: what the rays leaving a camera ray's hit add, clamped
  const Vector3f throughput = branch.throughput.cwiseProduct(attenuation);
  // the primary diffuse vertex's sky term, for the sky filter; `factor` times the sky light
  // (albedo 1) is its radiance here
  const auto primarySky = [&](const Vector3f& factor, const Vector3f& sky) {
    if (!branch.primary || !sample.primary) return;
    PathFeatures& p = *sample.primary;
    p.skyWeight = throughput.cwiseProduct(factor);
    p.sky = p.skyWeight.cwiseProduct(sky);
    p.depth = branch.distance + hit.t;
    p.objectId = hit.objectId;
    p.normal = wo.dot(hit.ns) >= 0.0f ? hit.ns : Vector3f(-hit.ns);
  };
  const auto follow = [&](const ScatterSample& s, const Vector3f& factor, bool primary) {
    const Branch next{branch.weight * factor.maxCoeff(), throughput.cwiseProduct(factor), branch.distance + hit.t,
                      branch.primary && primary};
    if (!(next.weight >= kWhittedCutoff)) return;
    Vector3f medium = absorption;
    Cone cone2{width, cone.spread};
    if (s.transmitted && hit.material) {
      const bool entering = wo.dot(hit.ng) > 0.0f;
      medium = entering ? material.absorption : Vector3f::Zero();
      cone2.spread *= entering ? 1.0f / material.ior : material.ior;
    }
    const Traced t = trace(f.leave(hit, s.direction), s.direction, depth + 1, medium, next, cone2, sample, counters, nullptr);
    Traced& to = depth == 0 ? secondary : radiance;
    to.value += factor.cwiseProduct(t.value);
    if (sample.edges) to.edge += factor.cwiseProduct(t.edge);
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
    case MaterialType::Diffuse: {
      const Direct d = direct(hit, wo, sample, counters);
      const Vector3f light = d.lights + d.sky;
      primarySky(albedo, d.sky);
      radiance.value = albedo.cwiseProduct(light);
      if (sample.edges) radiance.edge = edgeAlbedo.cwiseProduct(light);
      break;
    }
    case MaterialType::Mirror:
      if (sampleMaterial(material, hit.albedo, wo, hit.ns, hit.ng, 0.0f, 0.5f, 0.5f, s)) follow(s, s.weight, true);
      break;
    case MaterialType::Dielectric: {
      const float F = fresnel();
      if (F > 0.0f && sampleMaterial(material, hit.albedo, wo, hit.ns, hit.ng, 0.0f, 0.5f, 0.5f, s))
        follow(s, Vector3f::Constant(F), F > 0.5f);
      if (F < 1.0f && sampleMaterial(material, hit.albedo, wo, hit.ns, hit.ng, kAlmostOne, 0.5f, 0.5f, s))
        follow(s, Vector3f::Constant(1.0f - F), F <= 0.5f);
      break;
    }
    case MaterialType::Translucent: {
      const float F = fresnel();
      if (F > 0.0f && sampleMaterial(material, hit.albedo, wo, hit.ns, hit.ng, 0.0f, 0.5f, 0.5f, s) && !s.transmitted)
        follow(s, Vector3f::Constant(F), false);
      const Direct d = direct(hit, wo, sample, counters);
      const Vector3f light = (d.lights + d.sky) * (1.0f - F);
      primarySky(albedo.cwiseProduct(albedo) * (1.0f - F), d.sky);
      radiance.value += albedo.cwiseProduct(albedo).cwiseProduct(light);
      if (sample.edges) radiance.edge += edgeAlbedo.cwiseProduct(edgeAlbedo).cwiseProduct(light);
      break;
    }
  }
  if (depth == 0) {
    const float most = settings_.whitted.clampSecondary;
    radiance.value += clampedTo(secondary.value, most);
    radiance.edge += clampedTo(secondary.edge, most);
  }
  if (!sample.edges) return {attenuation.cwiseProduct(radiance.value), Vector3f::Zero()};
  return {attenuation.cwiseProduct(radiance.value), attenuation.cwiseProduct(radiance.edge)};
}

}  // namespace

std::unique_ptr<Integrator> makeWhittedIntegrator(const FrameScene& scene, const RenderSettings& settings) {
  return std::make_unique<WhittedIntegrator>(scene, settings);
}

}  // namespace kurage::render
