// Edge-avoiding a-trous denoiser; see denoise.h.
#include "render/denoise.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

namespace kurage::render {

using Eigen::Vector3f;

namespace {

constexpr float kAlbedoFloor = 0.02f;  // below this the colour is filtered as it is
constexpr std::array<float, 5> kB3{1.0f / 16.0f, 1.0f / 4.0f, 3.0f / 8.0f, 1.0f / 4.0f, 1.0f / 16.0f};

Vector3f demodulator(const Vector3f& albedo) {
  Vector3f d;
  for (int c = 0; c < 3; ++c) d[c] = albedo[c] > kAlbedoFloor ? albedo[c] : 1.0f;
  return d;
}

}  // namespace

Image denoise(const Image& noisy, const FeatureBuffers& f, const DenoiseSettings& s, double samplesPerPixel) {
  const int w = noisy.width(), h = noisy.height();
  const size_t n = size_t(w) * size_t(h);
  if (f.width != w || f.height != h || f.albedo.size() != n || f.normal.size() != n)
    throw std::invalid_argument("denoise: the feature buffers do not match the image");
  if (s.iterations < 1 || s.iterations > 10 || !(s.colourSigma > 0.0f) || !(s.normalSigma > 0.0f) ||
      !(s.albedoSigma > 0.0f) || !(samplesPerPixel > 0.0))
    throw std::invalid_argument("denoise: iterations must be in [1, 10], the sigmas and the samples per pixel > 0");
  // The noise falls as 1/sqrt(samples): so does the colour difference that marks an edge.
  const float colourSigma = s.colourSigma * float(std::sqrt(4.0 / samplesPerPixel));
  std::vector<Vector3f> current(n), next(n);
  std::vector<float> mean(n);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y) * size_t(w) + size_t(x);
      current[i] = noisy.at(x, y).head<3>().cwiseQuotient(demodulator(f.albedo[i]));
    }
  const float invNormal = 1.0f / (s.normalSigma * s.normalSigma);
  const float invAlbedo = 1.0f / (s.albedoSigma * s.albedoSigma);
  for (int pass = 0; pass < s.iterations; ++pass) {
    const int step = 1 << pass;
    const float sigma = colourSigma * std::pow(0.7071f, float(pass));  // narrower as the noise goes
    const float invColour = 1.0f / (sigma * sigma);
    // Each pixel's mean channel, for the relative colour distance.
    tbb::parallel_for(size_t(0), n, [&](size_t i) { mean[i] = current[i].sum() / 3.0f; });
    // Rows in parallel: each pass reads `current` and writes its own rows of `next`, so the result
    // does not depend on the thread count.
    tbb::parallel_for(tbb::blocked_range<int>(0, h, 8), [&](const tbb::blocked_range<int>& rows) {
      for (int y = rows.begin(); y < rows.end(); ++y)
        for (int x = 0; x < w; ++x) {
          const size_t p = size_t(y) * size_t(w) + size_t(x);
          const Vector3f& cp = current[p];
          Vector3f sum = Vector3f::Zero();
          float weights = 0.0f;
          for (int dy = -2; dy <= 2; ++dy) {
            const int qy = y + dy * step;
            if (qy < 0 || qy >= h) continue;
            for (int dx = -2; dx <= 2; ++dx) {
              const int qx = x + dx * step;
              if (qx < 0 || qx >= w) continue;
              const size_t q = size_t(qy) * size_t(w) + size_t(qx);
              const Vector3f& cq = current[q];
              const float scale = 1e-3f + 0.5f * (mean[p] + mean[q]);  // relative colour distance
              const float colour = (cp - cq).squaredNorm() / (scale * scale) * invColour;
              const float normal = (f.normal[p] - f.normal[q]).squaredNorm() * invNormal;
              const float albedo = (f.albedo[p] - f.albedo[q]).squaredNorm() * invAlbedo;
              const float weight = kB3[size_t(dx + 2)] * kB3[size_t(dy + 2)] * expNegative(colour + normal + albedo);
              sum += weight * cq;
              weights += weight;
            }
          }
          next[p] = weights > 0.0f ? Vector3f(sum / weights) : cp;
        }
    });
    current.swap(next);
  }
  Image out = noisy;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y) * size_t(w) + size_t(x);
      out.at(x, y).head<3>() = current[i].cwiseProduct(demodulator(f.albedo[i]));
    }
  return out;
}

}  // namespace kurage::render
