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
  if (f.width != w || f.height != h || f.albedo.size() != n || f.normal.size() != n ||
      !(f.sun.empty() || f.sun.size() == n))
    throw std::invalid_argument("denoise: the feature buffers do not match the image");
  if (s.iterations < 1 || s.iterations > 10 || !(s.colourSigma > 0.0f) || !(s.normalSigma > 0.0f) ||
      !(s.albedoSigma > 0.0f) || !(samplesPerPixel > 0.0))
    throw std::invalid_argument("denoise: iterations must be in [1, 10], the sigmas and the samples per pixel > 0");
  // The noise falls as 1/sqrt(samples): so does the colour difference that marks an edge.
  const float colourSigma = s.colourSigma * float(std::sqrt(4.0 / samplesPerPixel));
  const float invNormal = 1.0f / (s.normalSigma * s.normalSigma);
  const float invAlbedo = 1.0f / (s.albedoSigma * s.albedoSigma);
  // Planes (one float per pixel each) so that a tap is applied to a run of pixels of a row at
  // once, which the compiler vectorises: the colour (divided by the albedo; each pass writes the
  // next three planes), its mean channel, the normal and the albedo.
  std::array<std::vector<float>, 13> planes;
  for (auto& plane : planes) plane.resize(n);
  float *R = planes[0].data(), *G = planes[1].data(), *B = planes[2].data(), *M = planes[3].data();
  const float *NX = planes[4].data(), *NY = planes[5].data(), *NZ = planes[6].data();
  const float *AX = planes[7].data(), *AY = planes[8].data(), *AZ = planes[9].data();
  float *nextR = planes[10].data(), *nextG = planes[11].data(), *nextB = planes[12].data();
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y) * size_t(w) + size_t(x);
      const Vector3f unfiltered = f.sun.empty() ? Vector3f::Zero() : f.sun[i];
      const Vector3f c = (noisy.at(x, y).head<3>() - unfiltered).cwiseQuotient(demodulator(f.albedo[i]));
      R[i] = c.x(); G[i] = c.y(); B[i] = c.z();
      for (int k = 0; k < 3; ++k) planes[size_t(4 + k)][i] = f.normal[i][k];
      for (int k = 0; k < 3; ++k) planes[size_t(7 + k)][i] = f.albedo[i][k];
    }
  for (int pass = 0; pass < s.iterations; ++pass) {
    const int step = 1 << pass;
    const float sigma = colourSigma * std::pow(0.7071f, float(pass));  // narrower as the noise goes
    const float invColour = 1.0f / (sigma * sigma);
    tbb::parallel_for(size_t(0), n, [&](size_t i) { M[i] = (R[i] + G[i] + B[i]) / 3.0f; });  // for the relative colour distance
    // Rows in parallel: each pass reads the planes and writes its own rows of the next ones, so the
    // result does not depend on the thread count. Each pixel sums its taps in the order (dy, dx),
    // taps outside the image left out.
    tbb::parallel_for(tbb::blocked_range<int>(0, h, 8), [&](const tbb::blocked_range<int>& rows) {
      std::vector<float> sums(4 * size_t(w));
      float* __restrict sr = sums.data();
      float* __restrict sg = sr + w;
      float* __restrict sb = sg + w;
      float* __restrict sw = sb + w;
      for (int y = rows.begin(); y < rows.end(); ++y) {
        std::fill(sums.begin(), sums.end(), 0.0f);
        const size_t row = size_t(y) * size_t(w);
        for (int dy = -2; dy <= 2; ++dy) {
          const int qy = y + dy * step;
          if (qy < 0 || qy >= h) continue;
          for (int dx = -2; dx <= 2; ++dx) {
            const int shift = dx * step;
            const int x0 = std::max(0, -shift), x1 = std::min(w, w - shift);
            const float wxy = kB3[size_t(dx + 2)] * kB3[size_t(dy + 2)];
            const size_t qrow = size_t(qy) * size_t(w) + size_t(shift);  // q = qrow + x
            // Vectorised by GCC (the sums and the planes never overlap; render/CMakeLists.txt says
            // why this file needs -fno-trapping-math too). Clang, which builds the fuzz targets,
            // does not take the hint here and would warn.
#if defined(__GNUC__) && !defined(__clang__)
#pragma omp simd
#endif
            for (int x = x0; x < x1; ++x) {
              const size_t p = row + size_t(x), q = qrow + size_t(x);
              const float scale = 1e-3f + 0.5f * (M[p] + M[q]);  // relative colour distance
              const float cr = R[p] - R[q], cg = G[p] - G[q], cb = B[p] - B[q];
              const float colour = (cr * cr + cg * cg + cb * cb) / (scale * scale) * invColour;
              const float nx = NX[p] - NX[q], ny = NY[p] - NY[q], nz = NZ[p] - NZ[q];
              const float normal = (nx * nx + ny * ny + nz * nz) * invNormal;
              const float ax = AX[p] - AX[q], ay = AY[p] - AY[q], az = AZ[p] - AZ[q];
              const float albedo = (ax * ax + ay * ay + az * az) * invAlbedo;
              const float weight = wxy * expNegative(colour + normal + albedo);
              sr[x] += weight * R[q]; sg[x] += weight * G[q]; sb[x] += weight * B[q];
              sw[x] += weight;
            }
          }
        }
        for (int x = 0; x < w; ++x) {
          const size_t p = row + size_t(x);
          const bool any = sw[x] > 0.0f;
          nextR[p] = any ? sr[x] / sw[x] : R[p];
          nextG[p] = any ? sg[x] / sw[x] : G[p];
          nextB[p] = any ? sb[x] / sw[x] : B[p];
        }
      }
    });
    std::swap(R, nextR); std::swap(G, nextG); std::swap(B, nextB);
  }
  Image out = noisy;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y) * size_t(w) + size_t(x);
      out.at(x, y).head<3>() = Vector3f(R[i], G[i], B[i]).cwiseProduct(demodulator(f.albedo[i]));
      if (!f.sun.empty()) out.at(x, y).head<3>() += f.sun[i];
    }
  return out;
}

}  // namespace kurage::render
