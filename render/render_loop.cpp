// See render_loop.h.
#include "render/render_loop.h"

#include "render/sampling.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cmath>

namespace kurage::render {

namespace {
using Eigen::Vector3f;
constexpr int kTileSize = 16;
}  // namespace

Image renderImage(const CameraRays& camera, const Integrator& integrator,
                  const RenderSettings& settings, RayCounters& totals, FeatureBuffers* features,
                  const std::function<bool()>& stop) {
  const int width = settings.width, height = settings.height;
  Image image(width, height);
  if (features) {
    features->width = width;
    features->height = height;
    features->albedo.assign(size_t(width) * size_t(height), Vector3f::Zero());
    features->normal = features->albedo;
    features->sun = features->albedo;
  }
  // Samples are taken in batches of `batch` up to `most`; only adaptive sampling stops early, and
  // its sequence is open-ended (length 0 for the integrator's cameraSample).
  const AdaptiveSettings& adaptive = settings.adaptive;
  const bool adapting = adaptive.enabled && integrator.noisy();
  const int batch = adapting ? adaptive.minSamples : settings.samplesPerPixel;
  const int most = adapting ? adaptive.maxSamples : settings.samplesPerPixel;
  const int length = adapting ? 0 : settings.samplesPerPixel;
  const auto seed = static_cast<uint32_t>(settings.seed);
  const int tilesX = (width + kTileSize - 1) / kTileSize;
  const int tilesY = (height + kTileSize - 1) / kTileSize;
  std::atomic<uint64_t> primaryRays{0}, totalRays{0}, samples{0};
  tbb::parallel_for(tbb::blocked_range<int>(0, tilesX * tilesY), [&](const tbb::blocked_range<int>& tiles) {
    RayCounters counters;
    for (int tile = tiles.begin(); tile != tiles.end(); ++tile) {
      const int x0 = (tile % tilesX) * kTileSize, y0 = (tile / tilesX) * kTileSize;
      for (int y = y0; y < std::min(y0 + kTileSize, height); ++y)
        for (int x = x0; x < std::min(x0 + kTileSize, width); ++x) {
          if (stop && stop()) throw RenderStopped();  // TBB cancels the other tiles and rethrows
          const uint32_t pixel = static_cast<uint32_t>(y) * static_cast<uint32_t>(width) + static_cast<uint32_t>(x);
          Vector3f sum = Vector3f::Zero(), albedoSum = Vector3f::Zero(), normalSum = Vector3f::Zero(),
                   sunSum = Vector3f::Zero();
          int covered = 0;
          double lumSum = 0.0, lumSquares = 0.0;
          int n = 0;
          while (n < most) {
            const int batchEnd = std::min(n + batch, most);
            for (int s = n; s < batchEnd; ++s) {
              PixelSampler rng(pixel, static_cast<uint32_t>(s), seed);
              const CameraSample cs = integrator.cameraSample(pixel, s, length, rng);
              Vector3f origin, direction;
              camera.generate(static_cast<float>(x) + cs.film.x(), static_cast<float>(y) + cs.film.y(), cs.lens.x(),
                              cs.lens.y(), origin, direction);
              ++counters.primary;
              bool hitSomething = false;
              PathFeatures pf;
              const Vector3f value =
                  integrator.radiance(origin, direction, s, rng, counters, hitSomething, features ? &pf : nullptr);
              sum += value;
              albedoSum += pf.albedo;
              normalSum += pf.normal;
              sunSum += pf.sun;
              covered += hitSomething ? 1 : 0;
              const double lum = 0.2126 * value.x() + 0.7152 * value.y() + 0.0722 * value.z();
              lumSum += lum;
              lumSquares += lum * lum;
            }
            n = batchEnd;
            if (adapting) {
              const double mean = lumSum / n;
              const double variance = std::max(0.0, (lumSquares - n * mean * mean) / (n - 1));
              if (std::sqrt(variance / n) <= adaptive.relativeError * std::max(mean, 0.05)) break;
            }
          }
          if (features) {
            features->albedo[pixel] = albedoSum / float(n);
            features->normal[pixel] = normalSum / float(n);
            // normalised as the pixel's colour is, of which it is a part
            const int parts = settings.transparentBackground ? covered : n;
            features->sun[pixel] = parts > 0 ? Vector3f(sunSum / float(parts)) : Vector3f::Zero();
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
  totals.primary += primaryRays;
  totals.total += totalRays;
  totals.samples += samples;
  return image;
}

FrameLayers firstHitLayers(const FrameScene& scene, const CameraRays& camera, int width, int height) {
  FrameLayers layers(width, height);
  tbb::parallel_for(tbb::blocked_range<int>(0, height), [&](const tbb::blocked_range<int>& rows) {
    RayCounters counters;
    for (int y = rows.begin(); y != rows.end(); ++y)
      for (int x = 0; x < width; ++x) {
        Eigen::Vector3f origin, direction;
        camera.generate(float(x) + 0.5f, float(y) + 0.5f, 0.5f, 0.5f, origin, direction);
        const Hit hit = scene.intersect(origin, direction, counters);
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

}  // namespace kurage::render
