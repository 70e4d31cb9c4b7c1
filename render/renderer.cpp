// See renderer.h.
#include "render/renderer.h"

#include "render/embree_scene.h"
#include "render/frame_scene.h"
#include "render/integrators/integrator.h"
#include "render/render_loop.h"

#include <algorithm>
#include <chrono>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace kurage::render {

namespace {

void checkSettings(const RenderScene& scene, const RenderSettings& settings) {
  if (settings.width <= 0 || settings.height <= 0 || settings.samplesPerPixel <= 0)
    throw std::invalid_argument("render: width, height and samplesPerPixel must be positive");
  if (settings.maxDepth < 1) throw std::invalid_argument("render: maxDepth must be >= 1");
  if (settings.whitted.skyDirections < 1 || settings.whitted.lightSamples < 1)
    throw std::invalid_argument("render: whitted skyDirections and lightSamples must be >= 1");
  if (!(settings.whitted.adaptive.threshold > 0.0f) || settings.whitted.adaptive.minSamples < 1)
    throw std::invalid_argument("render: whitted adaptive anti-aliasing needs threshold > 0 and minSamples >= 1");
  const SkyFilterSettings& sky = settings.whitted.skyFilter;
  if (sky.enabled && !(sky.tile >= 2 && sky.normalCosine > -1.0f && sky.normalCosine <= 1.0f && sky.depthTolerance > 0.0f))
    throw std::invalid_argument("render: whitted sky filter needs tile >= 2, normalCosine in (-1, 1], depthTolerance > 0");
  if (settings.adaptive.enabled &&
      !(settings.adaptive.relativeError > 0.0f && settings.adaptive.minSamples >= 2 &&
        settings.adaptive.maxSamples >= settings.adaptive.minSamples))
    throw std::invalid_argument("render: adaptive sampling needs relativeError > 0 and 2 <= minSamples <= maxSamples");
  if (scene.sun.direction.squaredNorm() == 0.0f) throw std::invalid_argument("render: zero sun direction");
  if (!(scene.sun.angularDiameterDegrees >= 0.0f && scene.sun.angularDiameterDegrees < 90.0f))
    throw std::invalid_argument("render: sun angular diameter must be in [0, 90) degrees");
  if (scene.ground.enabled && scene.ground.normal.squaredNorm() == 0.0f)
    throw std::invalid_argument("render: zero ground normal");
  if (scene.clip.enabled && scene.clip.normal.squaredNorm() == 0.0f)
    throw std::invalid_argument("render: zero clip plane normal");
  if (scene.environment.type == EnvironmentType::Image && !scene.environment.image)
    throw std::invalid_argument("render: image environment without an image");
}

bool sameEnvironment(const Environment& a, const Environment& b) {
  return a.type == b.type && a.zenith == b.zenith && a.horizon == b.horizon && a.up == b.up &&
         a.intensity == b.intensity && a.rotationDegrees == b.rotationDegrees &&
         (a.image == b.image || (a.image && b.image && *a.image == *b.image));
}

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

struct Renderer::Impl {
  std::unique_ptr<EmbreeScene> geometry;  // made by the first frame
  // The environment's sampler and what it was built from (the environment, the ground's unit
  // normal when there is a ground).
  std::optional<EnvironmentSampler> sampler;
  Environment samplerEnvironment;
  std::optional<Eigen::Vector3f> samplerBelow;
  std::function<bool()> stop;

  const EnvironmentSampler& environmentSampler(const RenderScene& scene) {
    std::optional<Eigen::Vector3f> below;
    if (scene.ground.enabled) below = scene.ground.normal.normalized();
    if (!sampler || !sameEnvironment(samplerEnvironment, scene.environment) || samplerBelow != below) {
      sampler.emplace(scene.environment, below ? &*below : nullptr);
      samplerEnvironment = scene.environment;
      samplerBelow = below;
    }
    return *sampler;
  }
};

Renderer::Renderer() : impl_(std::make_unique<Impl>()) {}
Renderer::~Renderer() = default;
Renderer::Renderer(Renderer&&) noexcept = default;
Renderer& Renderer::operator=(Renderer&&) noexcept = default;

void Renderer::setStopCheck(std::function<bool()> stop) { impl_->stop = std::move(stop); }

int Renderer::staticBuilds() const { return impl_->geometry ? impl_->geometry->staticBuilds() : 0; }

Image Renderer::render(const RenderScene& scene, const RenderSettings& settings, RenderStats* stats,
                       FrameLayers* layers) {
  const auto start = std::chrono::steady_clock::now();
  checkSettings(scene, settings);
  const CameraRays camera(scene.camera, settings.width, settings.height);
  Impl& d = *impl_;
  if (!d.geometry) d.geometry = std::make_unique<EmbreeScene>();
  const int staticBuildsBefore = d.geometry->staticBuilds();
  const auto buildStart = std::chrono::steady_clock::now();
  d.geometry->update(scene);
  const double buildSeconds = secondsSince(buildStart);

  const bool path = settings.integrator == IntegratorType::Path;
  static const EnvironmentSampler kNoSampler;
  const EnvironmentSampler& sampler = path && settings.environmentSampling ? d.environmentSampler(scene) : kNoSampler;
  const FrameScene frame(scene, *d.geometry, sampler, settings.transmissiveShadows);
  const std::unique_ptr<Integrator> integrator =
      path ? makePathIntegrator(frame, settings) : makeWhittedIntegrator(frame, settings);

  const bool denoising = settings.denoise.enabled && integrator->noisy();
  FeatureBuffers features;
  RayCounters counters;
  Image image = renderImage(camera, *integrator, settings, counters, denoising ? &features : nullptr, d.stop,
                            stats ? &stats->pixelSamples : nullptr);
  d.geometry->throwIfError("rendering");
  if (d.stop && d.stop()) throw RenderStopped();  // before the denoiser and the layers
  if (denoising)
    image = denoise(image, features, settings.denoise,
                    std::max(1.0, double(counters.samples) / (double(settings.width) * double(settings.height))));
  if (layers) {
    std::vector<std::string> names = std::move(layers->objectNames);
    *layers = firstHitLayers(frame, camera, settings.width, settings.height);
    layers->objectNames = std::move(names);
    d.geometry->throwIfError("layers");
  }
  if (stats) {
    stats->primaryRays = counters.primary;
    stats->totalRays = counters.total;
    stats->samples = counters.samples;
    stats->seconds = secondsSince(start);
    stats->buildSeconds = buildSeconds;
    stats->staticBuilt = d.geometry->staticBuilds() != staticBuildsBefore;
  }
  return image;
}

Image renderFrame(const RenderScene& scene, const RenderSettings& settings, RenderStats* stats, FrameLayers* layers) {
  return Renderer().render(scene, settings, stats, layers);
}

}  // namespace kurage::render
