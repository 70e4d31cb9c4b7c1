// The render loop: the image in tiles of 16 x 16 pixels, rendered in parallel (TBB), each pixel
// the mean of its camera samples' radiance, which the integrator estimates (it knows no
// integrator beyond integrators/integrator.h).
//
// Per pixel: samplesPerPixel samples, or, with adaptive sampling and a noisy integrator, batches
// of minSamples until the standard error of the mean luminance L = 0.2126 R + 0.7152 G + 0.0722 B
// falls below relativeError max(mean, 0.05) (AdaptiveSettings, renderer.h). Sample s of pixel p
// draws its random numbers from PixelSampler(p, s, seed) alone, so the image is independent of
// the thread count and the tile order.
//
// Edge-adaptive anti-aliasing (integrators without noise; EdgeAdaptiveSettings, renderer.h): a
// first pass renders every pixel with minSamples samples (the uniform sample set of that count);
// both pixels of a horizontally or vertically adjacent pair are marked where their edge values
// (the mean of the samples' PathFeatures::edge, with the pixel's alpha) differ by more than the
// threshold in some channel (clamped and sRGB-encoded, as PNG shows a colour); a second pass renders the marked pixels again with samplesPerPixel samples, the uniform
// set of that count, dropping their first ones. The marks depend only on the first pass, so the
// image still depends on neither the thread count nor the tile order. Cost: minSamples per pixel, plus samplesPerPixel
// per marked pixel (an edge marks 2 to 3 pixels per pixel of its length).
//
// Film: colour = sum / n, alpha 1; with a transparent background alpha = covered / n (covered:
// samples whose camera ray met something) and colour = sum / covered (straight alpha).
// Denoiser features (denoise.h), when asked for: per pixel the mean albedo and normal of the
// samples' first non-specular vertex, and their sun light normalised as the colour is.
#pragma once

#include "render/camera.h"
#include "render/denoise.h"
#include "render/frame_layers.h"
#include "render/frame_scene.h"
#include "render/image.h"
#include "render/integrators/integrator.h"
#include "render/renderer.h"

#include <cstdint>
#include <vector>

namespace kurage::render {

// The frame's image; adds its rays and samples to `totals`. `features`, when given (a noisy
// integrator), is sized and filled. `stop`, when given, is asked before every pixel (from the
// worker threads): true throws RenderStopped (renderer.h). `pixelSamples`, when given, receives
// each pixel's number of camera samples (y * width + x).
Image renderImage(const CameraRays& camera, const Integrator& integrator,
                  const RenderSettings& settings, RayCounters& totals, FeatureBuffers* features,
                  const std::function<bool()>& stop = {}, std::vector<uint32_t>* pixelSamples = nullptr);

// The compositing layers (frame_layers.h): one ray through each pixel centre and the lens centre.
// objectNames stay empty.
FrameLayers firstHitLayers(const FrameScene& scene, const CameraRays& camera, int width, int height);

}  // namespace kurage::render
