// The renderer: frames of a RenderScene (scene.h) as linear radiance with alpha, by a headless
// Embree 3 ray tracer.
//
// A frame is made in four steps, each in its own file:
//   embree_scene.h            the geometry's BVHs (static meshes built once and kept, the moving
//                             geometry built every frame) and the ray queries
//   frame_scene.h             what the integrators see of the frame: hits with the analytic ground
//                             and area lights, shadow rays, the lights' derived quantities
//   integrators/integrator.h  the light transport, one file per integrator (path, whitted)
//   render_loop.h             tiles, camera samples, adaptive sampling, film and layers
// then, for the path integrator, the denoiser (denoise.h).
//
// A Renderer keeps what does not change from frame to frame of a run: the Embree device, the
// static meshes' BVH (rebuilt when they differ, scene.h) and the environment's importance sampler
// (rebuilt when the environment or the ground's normal differs). What a frame shows depends only
// on the scene, the settings and the seed, never on what the Renderer rendered before it, nor on
// the thread count or the order of tiles.
#pragma once

#include "render/denoise.h"
#include "render/frame_layers.h"
#include "render/image.h"
#include "render/scene.h"

#include <cstdint>
#include <functional>
#include <memory>
#include <stdexcept>
#include <vector>

namespace kurage::render {

// How radiance is estimated: "path", unbiased path tracing with next-event estimation
// (integrators/path.cpp), or "whitted", deterministic ray tracing with direct light at diffuse
// surfaces and no noise (integrators/whitted.cpp).
enum class IntegratorType { Path, Whitted };

// Edge-adaptive anti-aliasing (integrators without noise: whitted; render_loop.h): every pixel
// first takes minSamples sub-pixel samples; a pixel whose edge value (whitted: its colour with
// every filtered checker at its mean colour, so that only geometry, shadows and plain colours
// count) differs from one of its four neighbours' by more than threshold in some channel
// (sRGB-encoded, clamped to [0, 1]; alpha with a transparent background) is rendered again with
// samplesPerPixel samples, which replace its first ones. Each pixel is then exactly the uniform render's pixel at minSamples or at
// samplesPerPixel; uniform when minSamples >= samplesPerPixel. A pixel's own samples are no test:
// whitted's samples differ in their sky directions as well as in their positions. Off by default
// (what it gains on the jellyfish: docs/notebook/rendering.md).
struct EdgeAdaptiveSettings {
  bool enabled = false;
  float threshold = 0.02f;  // > 0
  int minSamples = 2;       // >= 1
};

// Interleaved sky directions and their cross-bilateral filter (whitted; integrators/whitted.cpp,
// sky_filter.h): the pixel at (x mod tile, y mod tile) = (a, b) turns its sky directions by its own
// offset of a tile x tile lattice (Keller & Heidrich 2001, "Interleaved sampling"), and the sky's
// share of each pixel's radiance, divided by its albedo and throughput (an irradiance), is averaged
// over the tile x tile pixels around it that show the same object with a normal within
// acos(normalCosine) and a depth within depthTolerance of the pixel's own (relative), so a pixel on
// a smooth surface sees tile^2 times its own sky directions. The sun, area lights and specular
// branches are not filtered. Off by default.
struct SkyFilterSettings {
  bool enabled = false;
  int tile = 4;                 // >= 2
  float normalCosine = 0.9f;    // in (-1, 1]
  float depthTolerance = 0.05f;  // > 0
};

struct WhittedSettings {
  int skyDirections = 16;  // shadow rays towards the sky per diffuse point, >= 1
  int lightSamples = 2;    // grid points per side on each area light, >= 1
  // checkers box-filtered over the pixel's ray-cone footprint (integrators/whitted.cpp)
  bool filterTextures = true;
  // The most a camera sample's secondary rays (the reflected and refracted ones from its first hit,
  // and all they see) add to it, per channel, linear (1 = the PNG's white); 0 = no clamp.
  // Bounds a sun glint seen by one sample in S to 1/S of a pixel (integrators/whitted.cpp).
  float clampSecondary = 1.0f;
  EdgeAdaptiveSettings adaptive;
  SkyFilterSettings skyFilter;
};

// Adaptive sampling (noisy integrators: path): every pixel takes minSamples paths, then more in
// batches of minSamples until the standard error of its mean luminance, sqrt(var / n) with var the
// luminance's sample variance, falls below relativeError times max(mean, 0.05) (the floor keeps
// dark pixels from demanding endless samples) or maxSamples is reached. samplesPerPixel is then
// ignored. Sub-pixel positions follow a (0,2)-sequence whose every prefix of 2^k is stratified.
struct AdaptiveSettings {
  bool enabled = false;
  float relativeError = 0.05f;  // > 0
  int minSamples = 8;           // >= 2
  int maxSamples = 256;         // >= minSamples
};

struct RenderSettings {
  int width = 640;
  int height = 360;
  int samplesPerPixel = 16;
  int maxDepth = 8;   // most scattering events on a path (1 = direct light only)
  int seed = 0;  // >= 0; another seed gives another, equally valid, noise pattern
  // Shadow rays pass through dielectric surfaces (Fresnel transmission, absorption, no bending;
  // frame_scene.h), and light sources are then counted on hit only after pure specular chains
  // from the camera: the light under water is far less noisy, at the price of caustics.
  // false = exact transport (caustics only from the sun's disk, noisy).
  bool transmissiveShadows = true;
  bool transparentBackground = false;  // alpha = fraction of camera rays that hit something;
                                       // the environment is then not seen directly
  // Next-event estimation for the environment (path integrator): at every diffuse or
  // translucent vertex one shadow ray towards a direction drawn by EnvironmentSampler (lights.h),
  // combined with the BSDF-sampled rays that escape to the sky by Veach's power heuristic. With
  // transmissive shadows the shadow ray passes water unbent, its radiance divided by ior^2 where
  // it leaves the water (Snell's window: exact for a flat surface over a parallel floor), and
  // escaping paths whose specular chain after the last diffuse vertex holds only refractions are
  // then not counted again. false: the sky is found only by escaping paths.
  bool environmentSampling = true;
  // Path integrator: where a camera ray first meets water or glass from outside, follow both the
  // Fresnel-reflected and the refracted ray (weights F, 1 - F) instead of choosing one at random;
  // removes the noise of that choice (the sky mirrored on the water) for one more path from there.
  bool fresnelSplitting = true;
  IntegratorType integrator = IntegratorType::Path;
  WhittedSettings whitted;
  AdaptiveSettings adaptive;
  // Path integrator: filter the frame with render/denoise.h, guided by the albedo and normal of
  // the first non-specular vertex of each camera path (gathered while tracing).
  DenoiseSettings denoise;
};

struct RenderStats {
  uint64_t primaryRays = 0;  // camera rays
  uint64_t totalRays = 0;    // every Embree query: camera, bounce and shadow rays
  uint64_t samples = 0;      // paths (or, whitted, sub-pixel trees) traced over the whole image
  double seconds = 0.0;      // wall time of the frame, BVH builds included
  double buildSeconds = 0.0;  // of which building the BVHs (the static one only when rebuilt)
  bool staticBuilt = false;   // the static meshes' BVH was (re)built for this frame
  std::vector<uint32_t> pixelSamples;  // camera samples traced per pixel (index y * width + x)
};

// Thrown by Renderer::render when its stop check asked it to end the frame early.
class RenderStopped : public std::runtime_error {
public:
  RenderStopped() : std::runtime_error("rendering stopped before the frame was finished") {}
};

class Renderer {
public:
  Renderer();  // cheap: the Embree device is made by the first frame
  ~Renderer();
  Renderer(Renderer&&) noexcept;
  Renderer& operator=(Renderer&&) noexcept;

  // Renders one frame (linear radiance, alpha). Throws std::invalid_argument for bad settings or
  // scene data and std::runtime_error if Embree fails. `layers`, when given, receives what the
  // camera ray through each pixel centre (lens centre) meets first (frame_layers.h); its
  // objectNames are left as they were. `scene` is read only during the call.
  Image render(const RenderScene& scene, const RenderSettings& settings, RenderStats* stats = nullptr,
               FrameLayers* layers = nullptr);

  // Asked before every pixel, from the worker threads (so it must be thread-safe and cheap):
  // true ends the frame at once with RenderStopped. Empty (the default): never asked.
  void setStopCheck(std::function<bool()> stop);

  // How many times the static meshes' BVH was built so far (for tests).
  int staticBuilds() const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// One frame by a Renderer of its own (everything built for it).
Image renderFrame(const RenderScene& scene, const RenderSettings& settings, RenderStats* stats = nullptr,
                  FrameLayers* layers = nullptr);

}  // namespace kurage::render
