// See sky_filter.h.
#include "render/sky_filter.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

namespace kurage::render {

SkyBuffers::SkyBuffers(int w, int h)
    : width(w), height(h), sky(size_t(w) * size_t(h), Eigen::Vector3f::Zero()), weight(sky), normal(sky),
      depth(sky.size(), 0.0f), objectId(sky.size(), kObjectSky) {}

void filterSky(const SkyBuffers& b, const SkyFilterSettings& settings, Image& image) {
  using Eigen::Vector3f;
  const int width = b.width, height = b.height;
  const int tile = std::max(1, settings.tile);
  const int h = tile / 2;
  const bool even = tile % 2 == 0;
  const auto axisWeight = [&](int d) { return even && std::abs(d) == h ? 0.5f : 1.0f; };
  // the irradiance estimate E of pixel i, or false where it has none
  const auto estimate = [&](size_t i, Vector3f& e) {
    if (b.objectId[i] == kObjectSky || !(b.weight[i].minCoeff() > 0.0f)) return false;
    e = b.sky[i].cwiseQuotient(b.weight[i]);
    return true;
  };
  std::vector<Vector3f> filtered(b.sky.size());
  std::vector<uint8_t> done(b.sky.size(), 0);
  tbb::parallel_for(tbb::blocked_range<int>(0, height), [&](const tbb::blocked_range<int>& rows) {
    for (int y = rows.begin(); y != rows.end(); ++y)
      for (int x = 0; x < width; ++x) {
        const size_t i = size_t(y) * size_t(width) + size_t(x);
        Vector3f own;
        if (!estimate(i, own)) continue;
        const float length = b.normal[i].norm();
        if (!(length > 0.0f)) continue;
        const Vector3f n = b.normal[i] / length;
        const float depth = b.depth[i], tolerance = settings.depthTolerance * depth;
        Vector3f sum = Vector3f::Zero();
        float total = 0.0f;
        for (int dy = -h; dy <= h; ++dy) {
          const int yj = y + dy;
          if (yj < 0 || yj >= height) continue;
          for (int dx = -h; dx <= h; ++dx) {
            const int xj = x + dx;
            if (xj < 0 || xj >= width) continue;
            const size_t j = size_t(yj) * size_t(width) + size_t(xj);
            Vector3f e;
            if (b.objectId[j] != b.objectId[i] || !estimate(j, e)) continue;
            if (!(std::abs(b.depth[j] - depth) <= tolerance)) continue;
            if (!(n.dot(b.normal[j]) >= settings.normalCosine * b.normal[j].norm())) continue;
            const float w = axisWeight(dx) * axisWeight(dy);
            sum += w * e;
            total += w;
          }
        }
        filtered[i] = b.weight[i].cwiseProduct(sum / total);
        done[i] = 1;
      }
  });
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const size_t i = size_t(y) * size_t(width) + size_t(x);
      if (done[i]) image.at(x, y).head<3>() += filtered[i] - b.sky[i];
    }
}

}  // namespace kurage::render
