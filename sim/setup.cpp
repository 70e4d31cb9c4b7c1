#include "sim/setup.h"

#include <cmath>

namespace kurage::sim {

std::vector<Eigen::Vector3f> latticePoints(const FluidBlock& block, float spacing) {
  std::vector<Eigen::Vector3f> points;
  const Eigen::Vector3f extent = block.max - block.min;
  Eigen::Vector3i count;
  for (int a = 0; a < 3; ++a) {
    // Points at min + (i + 1/2) l for i = 0 .. n-1, with (n) l <= extent (+ a rounding margin).
    count[a] = std::max(0, static_cast<int>(std::floor(extent[a] / spacing + 1e-4f)));
  }
  points.reserve(size_t(count.prod()));
  for (int k = 0; k < count.z(); ++k)
    for (int j = 0; j < count.y(); ++j)
      for (int i = 0; i < count.x(); ++i)
        points.emplace_back(block.min + spacing * Eigen::Vector3f(i + 0.5f, j + 0.5f, k + 0.5f));
  return points;
}

}  // namespace kurage::sim
