#include "sim/boundary_particles.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>

namespace kurage::sim {

namespace {
// Lattice coordinates along one axis: the interior lattice from `lo` (first point half a spacing
// inside), and `layers` points beyond each side, continuing it outwards from each wall.
std::vector<float> axisCoordinates(float lo, float hi, float l, int layers) {
  std::vector<float> c;
  for (int k = layers - 1; k >= 0; --k) c.push_back(lo - (float(k) + 0.5f) * l);
  for (int k = 0;; ++k) {
    const float v = lo + (float(k) + 0.5f) * l;
    if (v > hi - 0.5f * l + 1e-4f * l) break;
    c.push_back(v);
  }
  for (int k = 0; k < layers; ++k) c.push_back(hi + (float(k) + 0.5f) * l);
  return c;
}
}  // namespace

BoundaryParticles::BoundaryParticles(const ContainerParams& box, float spacing, float supportRadius, float volume)
    : inner_(box), h_(supportRadius), h2_(supportRadius * supportRadius), volume_(volume) {
  const Eigen::Vector3f extent = box.max - box.min;
  if (extent.minCoeff() < supportRadius)
    throw std::invalid_argument("boundary particles: the container is thinner than the support radius");
  const int layers = int(std::ceil(supportRadius / spacing - 0.5f)) + 1;  // cover every sample within h
  std::array<std::vector<float>, 3> axes;
  for (int a = 0; a < 3; ++a) axes[a] = axisCoordinates(box.min[a], box.max[a], spacing, layers);
  std::vector<Eigen::Vector3f> samples;
  for (float z : axes[2])
    for (float y : axes[1])
      for (float x : axes[0]) {
        const Eigen::Vector3f p(x, y, z);
        const Eigen::Vector3f outside = (box.min - p).cwiseMax(p - box.max).cwiseMax(0.0f);
        if (outside.squaredNorm() == 0.0f) continue;                 // interior: fluid, not wall
        if (outside.squaredNorm() >= supportRadius * supportRadius) continue;  // out of every particle's reach
        samples.push_back(p);
      }
  // Static grid of cells of edge h over the samples' box, samples sorted by cell (x fastest).
  const float pad = float(layers + 1) * spacing;
  origin_ = box.min - Eigen::Vector3f::Constant(pad);
  const Eigen::Vector3f size = extent + Eigen::Vector3f::Constant(2.0f * pad);
  inverseCell_ = 1.0f / supportRadius;
  for (int a = 0; a < 3; ++a) dims_[a] = std::max(1, int(std::ceil(size[a] * inverseCell_)));
  const size_t cells = size_t(dims_.x()) * dims_.y() * dims_.z();
  std::vector<uint32_t> cellOfSample(samples.size());
  cellStart_.assign(cells + 1, 0);
  for (size_t s = 0; s < samples.size(); ++s) {
    const Eigen::Vector3i c = cellOf(samples[s].x(), samples[s].y(), samples[s].z());
    cellOfSample[s] = uint32_t((size_t(c.z()) * dims_.y() + c.y()) * dims_.x() + c.x());
    ++cellStart_[cellOfSample[s] + 1];
  }
  std::partial_sum(cellStart_.begin(), cellStart_.end(), cellStart_.begin());
  std::vector<uint32_t> fill(cellStart_.begin(), cellStart_.end() - 1);
  x_.resize(samples.size()); y_.resize(samples.size()); z_.resize(samples.size());
  for (size_t s = 0; s < samples.size(); ++s) {
    const uint32_t k = fill[cellOfSample[s]]++;
    x_[k] = samples[s].x(); y_[k] = samples[s].y(); z_[k] = samples[s].z();
  }
}

Eigen::Vector3i BoundaryParticles::cellOf(float px, float py, float pz) const {
  const Eigen::Vector3f q = (Eigen::Vector3f(px, py, pz) - origin_) * inverseCell_;
  Eigen::Vector3i c;
  for (int a = 0; a < 3; ++a) c[a] = std::clamp(int(std::floor(q[a])), 0, dims_[a] - 1);
  return c;
}

}  // namespace kurage::sim
