// See airborne.h. Neighbours are counted only for the fast particles, in a hash grid of cells of
// size R over the positions in the cells around them (none when no particle is fast); the counts
// are exact, so the result does not depend on the order.
#include "render/airborne.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <unordered_map>

namespace kurage::render {

namespace {
float ramp(float x, float zero, float one) { return std::clamp((x - zero) / (one - zero), 0.0f, 1.0f); }

uint64_t cellKey(int64_t x, int64_t y, int64_t z) {
  const auto u = [](int64_t v) { return uint64_t(v + (int64_t(1) << 20)) & ((uint64_t(1) << 21) - 1); };
  return (u(x) << 42) | (u(y) << 21) | u(z);
}
}  // namespace

std::vector<float> airborneRadiusScales(const std::vector<Eigen::Vector3f>& positions,
                                        const std::vector<Eigen::Vector3f>& velocities, float radius, float spacing,
                                        const AirborneParams& params) {
  if (velocities.size() != positions.size())
    throw std::invalid_argument("airborne: positions and velocities differ in number");
  std::vector<float> scales(positions.size(), 1.0f);
  if (!params.enabled) return scales;
  const bool ok = radius > 0.0f && spacing > 0.0f && params.radius > 0.0f && params.radius <= radius &&
                  params.speedFull > params.speedMin && params.fillMin > params.fillFull;
  if (!ok)
    throw std::invalid_argument("airborne: need R, spacing > 0, 0 < radius <= R, speed_full > speed_min, "
                                "fill_min > fill_full");
  const auto cell = [radius](const Eigen::Vector3f& p) {
    return Eigen::Array<int64_t, 3, 1>(int64_t(std::floor(p.x() / radius)), int64_t(std::floor(p.y() / radius)),
                                       int64_t(std::floor(p.z() / radius)));
  };
  // The fast particles' weights, and the cells around them (their neighbours' cells).
  std::vector<float> fast(positions.size());
  Eigen::Array<int64_t, 3, 1> lo = Eigen::Array<int64_t, 3, 1>::Constant(std::numeric_limits<int64_t>::max());
  Eigen::Array<int64_t, 3, 1> hi = -lo;
  for (size_t i = 0; i < positions.size(); ++i) {
    fast[i] = ramp(velocities[i].norm(), params.speedMin, params.speedFull);
    if (fast[i] == 0.0f) continue;
    lo = lo.min(cell(positions[i]) - 1);
    hi = hi.max(cell(positions[i]) + 1);
  }
  if ((lo > hi).any()) return scales;  // none is fast
  std::unordered_map<uint64_t, std::vector<uint32_t>> grid;
  for (size_t i = 0; i < positions.size(); ++i) {
    const Eigen::Array<int64_t, 3, 1> c = cell(positions[i]);
    if ((c >= lo).all() && (c <= hi).all()) grid[cellKey(c.x(), c.y(), c.z())].push_back(uint32_t(i));
  }
  const double full = 4.0 / 3.0 * std::numbers::pi * std::pow(double(radius) / spacing, 3.0);
  const float r2 = radius * radius;
  const float shrink = 1.0f - params.radius / radius;
  for (size_t i = 0; i < positions.size(); ++i) {
    if (fast[i] == 0.0f) continue;
    const Eigen::Vector3f& p = positions[i];
    const Eigen::Array<int64_t, 3, 1> c = cell(p);
    const int64_t cx = c.x(), cy = c.y(), cz = c.z();
    size_t n = 0;
    for (int64_t x = cx - 1; x <= cx + 1; ++x)
      for (int64_t y = cy - 1; y <= cy + 1; ++y)
        for (int64_t z = cz - 1; z <= cz + 1; ++z) {
          const auto it = grid.find(cellKey(x, y, z));
          if (it == grid.end()) continue;
          for (const uint32_t j : it->second) n += (positions[j] - p).squaredNorm() < r2;
        }
    const float sparse = 1.0f - ramp(float(double(n) / full), params.fillFull, params.fillMin);
    scales[i] = 1.0f - fast[i] * sparse * shrink;
  }
  return scales;
}

}  // namespace kurage::render
