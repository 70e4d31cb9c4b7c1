// A small edge-avoiding denoiser for path-traced frames, guided by feature buffers.
//
// Method: the edge-avoiding a-trous wavelet filter of Dammertz, Sewtz, Hanika & Lensch (2010,
// "Edge-avoiding A-Trous wavelet transform for fast global illumination filtering"): `iterations`
// passes of the 5x5 B3-spline kernel (1/16, 1/4, 3/8, 1/4, 1/16 per axis) with holes, the taps
// 2^i pixels apart in pass i, each tap weighted also by how alike it is to the centre pixel in
// colour, normal and albedo (Gaussians of the squared differences). Before filtering, the colour
// is divided by the albedo ("demodulated": lighting is smooth where texture is not), and
// multiplied back after, so checkerboards and texture edges stay sharp (as in SVGF, Schied et al.
// 2017). The colour distance is relative to the two pixels' brightness, and its width halves at
// every pass by sqrt(2) (the noise the earlier passes removed; Dammertz et al. halve it).
//
// Features, per pixel, averaged over its samples (the render loop fills them, render_loop.h): the albedo
// at the first non-specular vertex of the camera's path times the specular chain's throughput
// before it (so water and mirrors tint it), and that vertex's shading normal (0 where the path
// escaped to the sky or ended on a light; the albedo there is the chain's throughput).
//
// The sun's direct light at that vertex (times the same throughput) is part of the colour but
// nearly free of noise (one shadow ray towards a disk of half a degree: only anti-aliasing and
// penumbrae vary between samples), and it carries the sharpest lighting edges of a frame, the
// hard shadows. It is subtracted before filtering and added back after, so only the noisy rest
// (sky, area lights, bounces) is smoothed and shadow edges stay as sharp as the samples make them
// (the split of direct and indirect light of production denoisers, reduced to the one light
// that needs it). On the dam break at 960 x 540 and 16 spp it took the RMSE against a converged
// frame from 0.0163 to 0.0125 (docs/design/rendering.md).
//
// Limits: a heuristic, biased filter: it blurs lighting detail finer than the noise (small
// caustics, the sky's and area lights' soft shadow edges) and keeps fireflies it cannot tell
// from edges. Allocates one scratch image; call once per frame.
#pragma once

#include "render/image.h"

#include <Eigen/Core>

#include <cstdint>
#include <cstring>
#include <vector>

namespace kurage::render {

struct DenoiseSettings {
  bool enabled = false;
  // Defaults: the lowest RMSE against a 1,024-sample reference on the jellyfish at t = 8 s at 3
  // and 4 samples per pixel, over iterations 2-6 and the sigmas below halved and doubled; the
  // colour width then 4 -> 3, better on the dam break at both qualities and the same on the
  // jellyfish (docs/design/rendering.md, "The denoiser").
  int iterations = 3;          // passes; the widest reaches 2^(iterations+1) pixels
  float colourSigma = 3.0f;    // relative colour difference at which a tap's weight falls to 1/e, at 4 spp
  float normalSigma = 0.6f;    // |n_p - n_q| at which it falls to 1/e
  float albedoSigma = 0.2f;    // |a_p - a_q| at which it falls to 1/e
};

struct FeatureBuffers {
  int width = 0, height = 0;
  std::vector<Eigen::Vector3f> albedo;  // row-major, row 0 on top, as Image
  std::vector<Eigen::Vector3f> normal;
  // The sun's direct light at the first non-specular vertex, part of the colour: left out of the
  // filter and added back after it (empty: the whole colour is filtered).
  std::vector<Eigen::Vector3f> sun;
};

// The filtered image (alpha kept). The colour width is `colourSigma` at 4 samples per pixel and
// narrows as the noise does, as 1/sqrt(samplesPerPixel) (the frame's mean). Throws
// std::invalid_argument when the features do not match the image's size or the settings are out
// of range (iterations 1..10, sigmas > 0, samplesPerPixel > 0).
Image denoise(const Image& noisy, const FeatureBuffers& features, const DenoiseSettings& settings,
              double samplesPerPixel = 4.0);

// exp(-x) for x >= 0, within 1e-4 relative of std::exp, and exactly 0 from x >= 80: the filter's
// tap weights (std::exp took a third of the filter's time). exp(-x) = 2^-n e^(-r) with n the
// nearest integer to x / ln 2 and |r| <= ln 2 / 2, e^(-r) by its Taylor series to degree 4
// (truncation below 4.2e-5), evaluated in two short chains, 2^-n written into the float's exponent.
// Branch-free (a select, not a jump), so that loops over pixels calling it vectorise.
inline float expNegative(float x) {
  const bool inRange = x < 80.0f;  // false below float's normal range (e^-80 ~ 1.8e-35), and for NaN
  const float xc = inRange ? x : 80.0f;
  const float n = float(int(xc * 1.44269504f + 0.5f));
  const float r = xc - n * 0.693147181f;  // |r| <= ln 2 / 2
  const float r2 = r * r;
  const float e = (1.0f - r) + r2 * ((0.5f - r * (1.0f / 6.0f)) + r2 * (1.0f / 24.0f));
  const uint32_t bits = uint32_t(127 - int(n)) << 23;  // 2^-n, n <= 116
  float scale;
  std::memcpy(&scale, &bits, sizeof scale);
  return inRange ? e * scale : 0.0f;
}

}  // namespace kurage::render
