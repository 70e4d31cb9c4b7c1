// The path integrator (RenderSettings::integrator "path"): unidirectional path tracing, an
// unbiased Monte Carlo estimate of the rendering equation (Kajiya 1986).
//
// Next-event estimation at every non-specular vertex: one shadow ray to the sun (a direction in
// its cone), one to a uniform point on each area light, and, with
// RenderSettings::environmentSampling, one to a direction drawn by EnvironmentSampler (lights.h),
// weighted against BSDF sampling by Veach's power heuristic (Veach 1997, ch. 9), so no path is
// counted twice. The sun and the area lights are added on hit only after a specular bounce or at
// the camera (with transmissive shadows: only after pure specular chains from the camera, the
// light behind a dielectric having been estimated by the shadow ray through it). Russian roulette
// once a path's throughput falls below 1 (from the third bounce on, survival = max throughput),
// and a hard maximum of maxDepth scattering events. Beer-Lambert absorption exp(-sigma_a d)
// attenuates paths inside dielectric and translucent objects.
//
// With RenderSettings::fresnelSplitting, where the camera ray first meets a dielectric from
// outside, both branches are followed: the reflected one as a path of its own with weight F, the
// refracted one by this path with weight 1 - F, instead of choosing one with probabilities F and
// 1 - F: same expectation, no noise from the choice (a splitting estimator, Arvo & Kirk 1990).
//
// Camera samples: the sub-pixel positions of a Cranley-Patterson-rotated Hammersley set of n
// points (sampling.h pixelSamplePosition), or of the (0,2)-sequence when n is open-ended
// (pixelSamplePositionProgressive); the lens point from the sample's first two random numbers.
#include "render/integrators/integrator.h"
#include "render/renderer.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>

namespace kurage::render {
namespace {

using Eigen::Vector3f;

constexpr float kInfinity = std::numeric_limits<float>::infinity();

class PathIntegrator final : public Integrator {
public:
  PathIntegrator(const FrameScene& scene, const RenderSettings& settings) : f_(scene), settings_(settings) {}

  bool noisy() const override { return true; }

  CameraSample cameraSample(uint32_t pixel, int s, int n, PixelSampler& rng) const override {
    const auto seed = static_cast<uint32_t>(settings_.seed);
    CameraSample sample;
    sample.film = n > 0 ? pixelSamplePosition(uint32_t(s), uint32_t(n), pixel, seed)
                        : pixelSamplePositionProgressive(uint32_t(s), pixel, seed);
    const float lens1 = rng.next(), lens2 = rng.next();
    sample.lens = {lens1, lens2};
    return sample;
  }

  Vector3f radiance(const Vector3f& origin, const Vector3f& direction, uint32_t, int, int, PixelSampler& rng, RayCounters& counters,
                    bool& hitSomething, PathFeatures* features) const override {
    return trace(origin, direction, rng, counters, hitSomething, features, 0);
  }

private:
  Vector3f directLight(const Hit& hit, const Vector3f& wo, PixelSampler& rng, RayCounters& counters,
                       Vector3f* sunPart) const;
  Vector3f trace(Vector3f origin, Vector3f direction, PixelSampler& rng, RayCounters& counters, bool& hitSomething,
                 PathFeatures* features, int firstDepth) const;

  const FrameScene& f_;
  const RenderSettings& settings_;
};

const Material kGroundMaterial{};

// Direct light from the sun and the area lights at a non-specular vertex (one sample each), and
// from the environment when it is sampled (one direction, MIS-weighted against BSDF sampling).
// `sunPart`, when given, receives the sun's share of the sum.
Vector3f PathIntegrator::directLight(const Hit& hit, const Vector3f& wo, PixelSampler& rng, RayCounters& counters,
                                     Vector3f* sunPart) const {
  const FrameScene& f = f_;
  const Material& material = hit.material ? *hit.material : kGroundMaterial;
  Vector3f sum = Vector3f::Zero();
  // Sun: a uniformly sampled direction in its cone; irradiance * f cos (the cone's pdf cancels).
  const float u1 = rng.next(), u2 = rng.next();
  if (f.sunOn) {
    const Vector3f wi = f.sunCosMax < 1.0f ? sampleCone(f.toSun, f.sunCosMax, u1, u2) : f.toSun;
    const Vector3f fcos = evaluateDiffuseLobe(material, hit.albedo, wo, wi, hit.ns, hit.ng);
    if (fcos.maxCoeff() > 0.0f)
      sum += fcos.cwiseProduct(f.input.sun.irradiance).cwiseProduct(f.transmittance(f.leave(hit, wi), wi, kInfinity, counters));
  }
  if (sunPart) *sunPart = sum;
  // Area lights: a uniform point on each; pdf 1 / area converted to solid angle.
  for (const RectLight& l : f.input.rectLights) {
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
      sum += fcos.cwiseProduct(l.radiance)
                 .cwiseProduct(f.transmittance(f.leave(hit, wi), wi, distance * (1.0f - 1e-4f), counters)) *
             (cosLight * area / distance2);
  }
  // Environment: a direction by luminance, weighted by the power heuristic against the BSDF's
  // pdf for the same direction; trace() gives escaping BSDF samples the complementary weight.
  if (!f.environment.empty()) {
    const float e1 = rng.next(), e2 = rng.next();
    float pdfLight = 0.0f;
    const Vector3f wi = f.environment.sample(e1, e2, pdfLight);
    if (pdfLight > 0.0f) {
      const Vector3f fcos = evaluateDiffuseLobe(material, hit.albedo, wo, wi, hit.ns, hit.ng);
      const Vector3f from = f.leave(hit, wi);
      if (fcos.maxCoeff() > 0.0f && !f.groundBlocks(from, wi)) {
        const float weight = powerHeuristic(pdfLight, diffuseLobePdf(material, wo, wi, hit.ns, hit.ng)) / pdfLight;
        sum += fcos.cwiseProduct(environmentRadiance(f.input.environment, wi))
                   .cwiseProduct(f.transmittance(from, wi, kInfinity, counters)) *
               weight;
      }
    }
  }
  return sum;
}

// Radiance along a ray from path depth `firstDepth` (0: the camera ray; 1: the reflected branch
// of a split camera ray, which gathers no features).
Vector3f PathIntegrator::trace(Vector3f origin, Vector3f direction, PixelSampler& rng, RayCounters& counters,
                               bool& hitSomething, PathFeatures* features, int firstDepth) const {
  const FrameScene& f = f_;
  const RenderSettings& settings = settings_;
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
    const Hit hit = f.intersect(origin, direction, counters);
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
        radiance += throughput.cwiseProduct(environmentRadiance(f.input.environment, direction)) * weight;
      if (specular && f.sunOn && f.sunCosMax < 1.0f && direction.dot(f.toSun) >= f.sunCosMax)
        radiance += throughput.cwiseProduct(f.sunRadiance);
      break;
    }
    if (hit.kind == Hit::Light) {
      if (specular && direction.dot(hit.ng) < 0.0f)
        radiance += throughput.cwiseProduct(f.input.rectLights[size_t(hit.light)].radiance);
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
      radiance += throughput.cwiseProduct(directLight(hit, wo, rng, counters, first ? &sun : nullptr));
      if (first) features->sun = throughput.cwiseProduct(sun);
    } else
      rng.next(), rng.next();  // keep the dimension count independent of the material
    for (size_t i = 0; i < f.input.rectLights.size() && !hasDiffuseLobe(material.type); ++i) rng.next(), rng.next();
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
        radiance += fresnel * throughput.cwiseProduct(
                                  trace(f.leave(hit, s.direction), s.direction, rng, counters, ignored, nullptr, 1));
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
    origin = f.leave(hit, s.direction);
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

}  // namespace

std::unique_ptr<Integrator> makePathIntegrator(const FrameScene& scene, const RenderSettings& settings) {
  return std::make_unique<PathIntegrator>(scene, settings);
}

}  // namespace kurage::render
