// The seam between the render loop and the light transport. An integrator estimates the
// radiance arriving at the camera along one camera ray (the rendering equation's solution L(x, w)
// at the lens, Kajiya 1986), asking the frame's scene (frame_scene.h) for hits, shadow rays and
// lights; the render loop (render_loop.h) owns the tiles, the pixels' samples, the film and the
// compositing layers, and knows no integrator. One file per integrator:
//   path.cpp     unidirectional path tracing with next-event estimation (makePathIntegrator)
//   whitted.cpp  deterministic Whitted-style ray tracing (makeWhittedIntegrator)
// The design follows pbrt-v4's Integrator / RayIntegrator split (Pharr, Jakob & Humphreys,
// Physically Based Rendering, 4th ed., sec. 1.3.3 and 13.1), written for this renderer.
//
// Random numbers: each camera sample s of pixel p gets its own PixelSampler(p, s, seed)
// (sampling.h), fresh, handed first to cameraSample() and then, with the dimensions it left, to
// radiance(). So an image depends only on the scene, the settings and the seed, never on the
// thread count or the order of tiles.
#pragma once

#include "render/frame_scene.h"
#include "render/hit.h"
#include "render/sampling.h"

#include <Eigen/Core>

#include <cstdint>
#include <memory>

namespace kurage::render {

struct RenderSettings;

// Where a camera sample lies: film, the position inside the pixel, in [0,1)^2 (x right, y down);
// lens, the point on the lens in [0,1)^2 (used by a camera with an aperture).
struct CameraSample {
  Eigen::Vector2f film;
  Eigen::Vector2f lens;
};

// The denoiser's features of one camera path (denoise.h): albedo and normal at its first
// non-specular vertex, the albedo times the specular chain's throughput before it, and the sun's
// direct light there times that throughput (its share of the path's radiance). `edge`: what
// edge-adaptive anti-aliasing compares between neighbours (render_loop.h), set by integrators
// without noise (whitted: the radiance with filtered checkers at their mean colour).
// Whitted's sky filter (SkyFilterSettings, renderer.h): at the path's primary diffuse vertex (the
// first diffuse or translucent one along the heavier branch of each split), `sky` is its sky
// light's share of the radiance, `skyWeight` what that vertex's sky irradiance estimate is
// multiplied by to give it (throughput times albedo), `depth` the path's length to it (metres),
// `objectId` its object (kObjectSky: none), and `normal` its shading normal facing the path.
// Inputs: `wantEdge`, whether `edge` is asked for.
struct PathFeatures {
  Eigen::Vector3f albedo = Eigen::Vector3f::Zero();
  Eigen::Vector3f normal = Eigen::Vector3f::Zero();
  Eigen::Vector3f sun = Eigen::Vector3f::Zero();
  Eigen::Vector3f edge = Eigen::Vector3f::Zero();
  Eigen::Vector3f sky = Eigen::Vector3f::Zero();
  Eigen::Vector3f skyWeight = Eigen::Vector3f::Zero();
  float depth = 0.0f;
  uint32_t objectId = kObjectSky;
  bool wantEdge = false;
};

class Integrator {
public:
  virtual ~Integrator() = default;

  // Whether the estimate is noisy: adaptive sampling and the denoiser apply only then.
  virtual bool noisy() const = 0;

  // Camera sample s of the pixel with index `pixel` (y * width + x), of n samples in all, or of an
  // open-ended sequence when n is 0 (adaptive sampling): every prefix of 2^k samples must then be
  // well stratified. `rng` is the sample's own, fresh.
  virtual CameraSample cameraSample(uint32_t pixel, int s, int n, PixelSampler& rng) const = 0;

  // Radiance (linear RGB) arriving at the camera along the ray origin + t direction (unit) of
  // camera sample s of n (as for cameraSample) of pixel `pixel` (y * width + x). `hitSomething`: whether the ray met geometry, ground or a light (the pixel's
  // coverage). `features`, when given, receives the path's denoiser features (noisy integrators
  // only). Thread-safe.
  virtual Eigen::Vector3f radiance(const Eigen::Vector3f& origin, const Eigen::Vector3f& direction, uint32_t pixel,
                                   int s, int n,
                                   PixelSampler& rng, RayCounters& counters, bool& hitSomething,
                                   PathFeatures* features) const = 0;
};

// The integrators, each for one frame's scene and settings (both must outlive it).
std::unique_ptr<Integrator> makePathIntegrator(const FrameScene& scene, const RenderSettings& settings);
std::unique_ptr<Integrator> makeWhittedIntegrator(const FrameScene& scene, const RenderSettings& settings);

}  // namespace kurage::render
