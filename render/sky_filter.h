// The filter of whitted's interleaved sky term (SkyFilterSettings, renderer.h): a cross-bilateral
// box filter of the sky's irradiance over the tile around each pixel.
//
// A pixel's sky term S (its mean over the pixel's samples, part of its colour) is W E, W the
// factor its primary diffuse vertex's sky estimate is multiplied by (throughput times albedo, per
// channel) and E that estimate (irradiance / pi of albedo 1). The filter replaces S by
//   S' = W sum_j w_j E_j / sum_j w_j,   E_j = S_j / W_j (per channel),
// over the pixels j of the window: offsets -h..h in x and y, h = floor(N / 2), each axis weighted
// 1, and 1/2 at the ends when N is even, so every window holds each of the N x N interleaved sky
// sets with equal weight; w_j is that weight where j shows the same object as the pixel, with unit
// normals n . n_j >= normalCosine and |depth_j - depth| <= depthTolerance depth, 0 elsewhere. The
// albedo is divided out, so a texture's edges stay where they are and the filter crosses them.
// Pixels without a primary vertex, or whose samples met different objects (objectId kObjectSky),
// keep their own S and lend it to none. Demodulation and edge-stopping weights as in Dammertz et
// al. 2010, "Edge-avoiding a-trous wavelet transform for fast global illumination filtering"; the
// interleaved sets after Keller & Heidrich 2001, "Interleaved sampling".
#pragma once

#include "render/frame_layers.h"
#include "render/image.h"
#include "render/renderer.h"

#include <Eigen/Core>

#include <cstdint>
#include <vector>

namespace kurage::render {

// Per pixel (index y * width + x), normalised as the pixel's colour is.
struct SkyBuffers {
  int width = 0, height = 0;
  std::vector<Eigen::Vector3f> sky;     // S, the sky's share of the colour
  std::vector<Eigen::Vector3f> weight;  // W
  std::vector<Eigen::Vector3f> normal;  // the primary vertex's normal (mean of the samples')
  std::vector<float> depth;             // path length to the primary vertex, metres
  std::vector<uint32_t> objectId;       // its object; kObjectSky: not filtered
  SkyBuffers() = default;
  SkyBuffers(int w, int h);
};

// Replaces each filtered pixel's S in image's colour by S' (alpha untouched).
void filterSky(const SkyBuffers& buffers, const SkyFilterSettings& settings, Image& image);

}  // namespace kurage::render
