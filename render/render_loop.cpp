// See render_loop.h.
#include "render/render_loop.h"

#include "render/sampling.h"
#include "render/sky_filter.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <vector>

namespace kurage::render {

namespace {
using Eigen::Vector3f;
constexpr int kTileSize = 16;

// What a pixel's samples add up to.
struct PixelSums {
  Vector3f sum = Vector3f::Zero(), albedo = Vector3f::Zero(), normal = Vector3f::Zero(), sun = Vector3f::Zero();
  Vector3f edge = Vector3f::Zero();  // PathFeatures::edge, summed
  Vector3f sky = Vector3f::Zero(), skyWeight = Vector3f::Zero();  // PathFeatures' sky terms, summed
  float depth = 0.0f;
  uint32_t objectId = kObjectSky;  // the samples' primary object; kObjectSky where none or several
  bool firstObject = true;
  int covered = 0;  // samples whose camera ray met something
  int n = 0;
  double lumSum = 0.0, lumSquares = 0.0;
};

// A pixel's colour clamped to [0, 1] and sRGB-encoded, with its alpha: what edge-adaptive
// anti-aliasing compares (of the samples' PathFeatures::edge).
Eigen::Vector4f shown(const Eigen::Vector4f& pixel) {
  return {linearToSrgb(std::clamp(pixel.x(), 0.0f, 1.0f)), linearToSrgb(std::clamp(pixel.y(), 0.0f, 1.0f)),
          linearToSrgb(std::clamp(pixel.z(), 0.0f, 1.0f)), pixel.w()};
}

}  // namespace

Image renderImage(const CameraRays& camera, const Integrator& integrator,
                  const RenderSettings& settings, RayCounters& totals, FeatureBuffers* features,
                  const std::function<bool()>& stop, std::vector<uint32_t>* pixelSamples) {
  const int width = settings.width, height = settings.height;
  Image image(width, height);
  if (pixelSamples) pixelSamples->assign(size_t(width) * size_t(height), 0);
  if (features) {
    features->width = width;
    features->height = height;
    features->albedo.assign(size_t(width) * size_t(height), Vector3f::Zero());
    features->normal = features->albedo;
    features->sun = features->albedo;
  }
  const auto seed = static_cast<uint32_t>(settings.seed);
  const bool transparent = settings.transparentBackground;
  const bool skyFilter = settings.whitted.skyFilter.enabled && !integrator.noisy();
  SkyBuffers sky = skyFilter ? SkyBuffers(width, height) : SkyBuffers();

  // Samples first .. last - 1 of pixel (x, y), of a sequence of `length` (0: open-ended), added to
  // `p`; with `edges`, their PathFeatures too (whatever `features` says).
  const auto takeSamples = [&](int x, int y, int first, int last, int length, PixelSums& p, RayCounters& counters,
                               bool edges = false) {
    const uint32_t pixel = static_cast<uint32_t>(y) * static_cast<uint32_t>(width) + static_cast<uint32_t>(x);
    for (int s = first; s < last; ++s) {
      PixelSampler rng(pixel, static_cast<uint32_t>(s), seed);
      const CameraSample cs = integrator.cameraSample(pixel, s, length, rng);
      Vector3f origin, direction;
      camera.generate(static_cast<float>(x) + cs.film.x(), static_cast<float>(y) + cs.film.y(), cs.lens.x(),
                      cs.lens.y(), origin, direction);
      ++counters.primary;
      bool hitSomething = false;
      PathFeatures pf;
      pf.wantEdge = edges;
      const Vector3f value = integrator.radiance(origin, direction, pixel, s, length, rng, counters, hitSomething,
                                                 features || edges || skyFilter ? &pf : nullptr);
      p.sum += value;
      p.albedo += pf.albedo;
      p.normal += pf.normal;
      p.sun += pf.sun;
      p.edge += pf.edge;
      if (skyFilter) {
        p.sky += pf.sky;
        p.skyWeight += pf.skyWeight;
        p.depth += pf.depth;
        if (p.firstObject) p.objectId = pf.objectId;
        else if (pf.objectId != p.objectId) p.objectId = kObjectSky;
        p.firstObject = false;
      }
      p.covered += hitSomething ? 1 : 0;
      const double lum = 0.2126 * value.x() + 0.7152 * value.y() + 0.0722 * value.z();
      p.lumSum += lum;
      p.lumSquares += lum * lum;
    }
    p.n = std::max(p.n, last);
    counters.samples += uint64_t(last - first);
  };
  // The film: the pixel's value (and features) from its sums.
  const auto finish = [&](int x, int y, const PixelSums& p) {
    const int n = p.n;
    if (pixelSamples) (*pixelSamples)[size_t(y) * size_t(width) + size_t(x)] += uint32_t(n);
    if (features) {
      const size_t i = size_t(y) * size_t(width) + size_t(x);
      features->albedo[i] = p.albedo / float(n);
      features->normal[i] = p.normal / float(n);
      // normalised as the pixel's colour is, of which it is a part
      const int parts = transparent ? p.covered : n;
      features->sun[i] = parts > 0 ? Vector3f(p.sun / float(parts)) : Vector3f::Zero();
    }
    if (skyFilter) {
      const size_t i = size_t(y) * size_t(width) + size_t(x);
      const int parts = transparent ? p.covered : n;
      if (parts > 0) {
        sky.sky[i] = p.sky / float(parts);
        sky.weight[i] = p.skyWeight / float(parts);
      }
      sky.normal[i] = p.normal / float(n);
      sky.depth[i] = p.depth / float(n);
      sky.objectId[i] = parts > 0 ? p.objectId : kObjectSky;
    }
    Eigen::Vector4f value(0, 0, 0, 1);
    if (transparent) {
      value[3] = static_cast<float>(p.covered) / static_cast<float>(n);
      if (p.covered > 0) value.head<3>() = p.sum / static_cast<float>(p.covered);  // straight alpha
    } else {
      value.head<3>() = p.sum / static_cast<float>(n);
    }
    image.at(x, y) = value;
  };
  // Runs pixel(x, y, counters) over the image, tile by tile in parallel, for the pixels `wanted`
  // says (all when empty).
  const int tilesX = (width + kTileSize - 1) / kTileSize;
  const int tilesY = (height + kTileSize - 1) / kTileSize;
  std::atomic<uint64_t> primaryRays{0}, totalRays{0}, samples{0};
  const auto forPixels = [&](const std::vector<uint8_t>& wanted, const auto& pixel) {
    tbb::parallel_for(tbb::blocked_range<int>(0, tilesX * tilesY), [&](const tbb::blocked_range<int>& tiles) {
      RayCounters counters;
      for (int tile = tiles.begin(); tile != tiles.end(); ++tile) {
        const int x0 = (tile % tilesX) * kTileSize, y0 = (tile / tilesX) * kTileSize;
        for (int y = y0; y < std::min(y0 + kTileSize, height); ++y)
          for (int x = x0; x < std::min(x0 + kTileSize, width); ++x) {
            if (!wanted.empty() && !wanted[size_t(y) * size_t(width) + size_t(x)]) continue;
            if (stop && stop()) throw RenderStopped();  // TBB cancels the other tiles and rethrows
            pixel(x, y, counters);
          }
      }
      primaryRays += counters.primary;
      totalRays += counters.total;
      samples += counters.samples;
    });
  };

  const AdaptiveSettings& adaptive = settings.adaptive;
  const EdgeAdaptiveSettings& edges = settings.whitted.adaptive;
  const int spp = settings.samplesPerPixel;
  if (adaptive.enabled && integrator.noisy()) {
    // batches of minSamples of an open-ended sequence until the standard error is small enough
    forPixels({}, [&](int x, int y, RayCounters& counters) {
      PixelSums p;
      while (p.n < adaptive.maxSamples) {
        takeSamples(x, y, p.n, std::min(p.n + adaptive.minSamples, adaptive.maxSamples), 0, p, counters);
        const double mean = p.lumSum / p.n;
        const double variance = std::max(0.0, (p.lumSquares - p.n * mean * mean) / (p.n - 1));
        if (std::sqrt(variance / p.n) <= adaptive.relativeError * std::max(mean, 0.05)) break;
      }
      finish(x, y, p);
    });
  } else if (edges.enabled && !integrator.noisy() && edges.minSamples < spp) {
    // minSamples everywhere; then spp where neighbours differ
    const int first = edges.minSamples;
    std::vector<Eigen::Vector4f> values(size_t(width) * size_t(height));
    forPixels({}, [&](int x, int y, RayCounters& counters) {
      PixelSums p;
      takeSamples(x, y, 0, first, first, p, counters, true);
      finish(x, y, p);
      const float alpha = image.at(x, y).w();
      const int parts = transparent ? p.covered : p.n;
      const Vector3f edge = parts > 0 ? Vector3f(p.edge / float(parts)) : Vector3f::Zero();
      values[size_t(y) * size_t(width) + size_t(x)] = shown({edge.x(), edge.y(), edge.z(), alpha});
    });
    std::vector<uint8_t> refine(values.size(), 0);
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x) {
        const size_t i = size_t(y) * size_t(width) + size_t(x);
        const auto differs = [&](size_t j) {
          return (values[i] - values[j]).cwiseAbs().maxCoeff() > edges.threshold;
        };
        if (x + 1 < width && differs(i + 1)) refine[i] = refine[i + 1] = 1;
        if (y + 1 < height && differs(i + size_t(width))) refine[i] = refine[i + size_t(width)] = 1;
      }
    if (std::find(refine.begin(), refine.end(), uint8_t(1)) != refine.end())
      forPixels(refine, [&](int x, int y, RayCounters& counters) {
        PixelSums p;
        takeSamples(x, y, 0, spp, spp, p, counters);
        finish(x, y, p);
      });
  } else {
    forPixels({}, [&](int x, int y, RayCounters& counters) {
      PixelSums p;
      takeSamples(x, y, 0, spp, spp, p, counters);
      finish(x, y, p);
    });
  }
  if (skyFilter) filterSky(sky, settings.whitted.skyFilter, image);
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
