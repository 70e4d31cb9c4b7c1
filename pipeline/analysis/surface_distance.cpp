#include "pipeline/analysis/surface_distance.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace kurage::pipeline {

MetaballField::MetaballField(std::vector<Eigen::Vector3f> points, const render::MetaballParams& params)
    : points_(std::move(points)), params_(params) {
  if (points_.empty()) return;
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = -lo;
  for (const Eigen::Vector3f& q : points_) {
    centroid_ += q.cast<double>();
    lo = lo.cwiseMin(q.cast<double>());
    hi = hi.cwiseMax(q.cast<double>());
  }
  centroid_ /= double(points_.size());
  for (const Eigen::Vector3f& q : points_) reach_ = std::max(reach_, (q.cast<double>() - centroid_).norm());
  reach_ += params_.radius;
  const double r = params_.radius;
  lower_ = lo - Eigen::Vector3d::Constant(r);
  for (int a = 0; a < 3; ++a) cells_[a] = std::max(1, int(std::ceil((hi[a] + r - lower_[a]) / r)));
  const size_t cellCount = size_t(cells_.x()) * size_t(cells_.y()) * size_t(cells_.z());
  std::vector<uint32_t> cellOf(points_.size());
  cellStart_.assign(cellCount + 1, 0);
  for (size_t i = 0; i < points_.size(); ++i) {
    Eigen::Vector3i c;
    for (int a = 0; a < 3; ++a) c[a] = std::clamp(int((points_[i][a] - lower_[a]) / r), 0, cells_[a] - 1);
    cellOf[i] = uint32_t((size_t(c.z()) * size_t(cells_.y()) + size_t(c.y())) * size_t(cells_.x()) + size_t(c.x()));
    ++cellStart_[cellOf[i] + 1];
  }
  for (size_t c = 0; c < cellCount; ++c) cellStart_[c + 1] += cellStart_[c];
  cellPoints_.resize(points_.size());
  std::vector<uint32_t> fill(cellStart_.begin(), cellStart_.end() - 1);
  for (size_t i = 0; i < points_.size(); ++i) cellPoints_[fill[cellOf[i]]++] = uint32_t(i);
}

double MetaballField::operator()(const Eigen::Vector3d& x) const {
  if (points_.empty()) return 0.0;
  const double r = params_.radius, r2 = r * r;
  Eigen::Vector3i c;
  for (int a = 0; a < 3; ++a) c[a] = int(std::floor((x[a] - lower_[a]) / r));
  double f = 0.0;
  for (int k = c.z() - 1; k <= c.z() + 1; ++k)
    for (int j = c.y() - 1; j <= c.y() + 1; ++j)
      for (int i = c.x() - 1; i <= c.x() + 1; ++i) {
        if (i < 0 || j < 0 || k < 0 || i >= cells_.x() || j >= cells_.y() || k >= cells_.z()) continue;
        const size_t cell = (size_t(k) * size_t(cells_.y()) + size_t(j)) * size_t(cells_.x()) + size_t(i);
        for (uint32_t n = cellStart_[cell]; n < cellStart_[cell + 1]; ++n) {
          const double q = (points_[cellPoints_[n]].cast<double>() - x).squaredNorm() / r2;
          if (q < 1.0) f += params_.strength * (1.0 - q) * (1.0 - q);
        }
      }
  return f;
}

namespace {

// The outermost point along centre + s * direction, s in [0, far], where inside(s) turns true,
// marched inwards in steps of `step` and bisected to `tolerance`; negative when never inside.
template <class Inside>
double outermostCrossing(Inside inside, double far, double step, double tolerance) {
  double outside = far;
  if (inside(outside)) return -1.0;
  for (double s = far - step;; s -= step) {
    if (s < 0.0) s = 0.0;
    if (inside(s)) {
      double in = s, out = outside;
      while (out - in > tolerance) {
        const double mid = 0.5 * (in + out);
        (inside(mid) ? in : out) = mid;
      }
      return 0.5 * (in + out);
    }
    outside = s;
    if (s == 0.0) return -1.0;
  }
}

}  // namespace

SurfaceDistance surfaceDistance(const render::LevelSet& levelSet, const MetaballField& field,
                                const render::MetaballParams& params, int rays) {
  SurfaceDistance d;
  const double voxel = params.voxelSize;
  const double far = field.reach() + 2.0 * voxel;
  const double step = 0.1 * std::min<double>(params.radius, voxel);
  const double tolerance = 1e-6 * voxel;
  const Eigen::Vector3d c = field.centroid();
  double sum = 0.0, sumSquares = 0.0;
  const double golden = std::numbers::pi * (3.0 - std::sqrt(5.0));
  for (int k = 0; k < rays; ++k) {
    const double z = 1.0 - (2.0 * k + 1.0) / rays;
    const double rho = std::sqrt(std::max(0.0, 1.0 - z * z));
    const Eigen::Vector3d dir(rho * std::cos(golden * k), rho * std::sin(golden * k), z);
    const double exact = outermostCrossing([&](double s) { return field(c + s * dir) > params.threshold; }, far,
                                           step, tolerance);
    const double level = outermostCrossing(
        [&](double s) { return levelSet.sample((c + s * dir).cast<float>()) < 0.0f; }, far, step, tolerance);
    if (exact < 0.0 || level < 0.0) {
      d.misses += (exact < 0.0) != (level < 0.0);
      continue;
    }
    const double e = std::fabs(level - exact);
    sum += e;
    sumSquares += e * e;
    d.max = std::max(d.max, e);
    ++d.rays;
  }
  if (d.rays) {
    d.mean = sum / d.rays;
    d.rms = std::sqrt(sumSquares / d.rays);
  }
  return d;
}

}  // namespace kurage::pipeline
