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

namespace kurage::render {

// The frame's image; adds its rays and samples to `totals`. `features`, when given (a noisy
// integrator), is sized and filled. `stop`, when given, is asked before every pixel (from the
// worker threads): true throws RenderStopped (renderer.h).
Image renderImage(const CameraRays& camera, const Integrator& integrator,
                  const RenderSettings& settings, RayCounters& totals, FeatureBuffers* features,
                  const std::function<bool()>& stop = {});

// The compositing layers (frame_layers.h): one ray through each pixel centre and the lens centre.
// objectNames stay empty.
FrameLayers firstHitLayers(const FrameScene& scene, const CameraRays& camera, int width, int height);

}  // namespace kurage::render
