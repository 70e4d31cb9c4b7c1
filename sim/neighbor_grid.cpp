#include "sim/neighbor_grid.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace kurage::sim {

void NeighborGrid::configure(const Eigen::Vector3f& boxMin, const Eigen::Vector3f& boxMax, float minCellSize) {
  if (!(minCellSize > 0.0f)) throw std::invalid_argument("neighbour grid: cell size must be > 0");
  cellSize_ = minCellSize;
  inverseCellSize_ = 1.0f / cellSize_;
  origin_ = boxMin;
  const Eigen::Vector3f extent = (boxMax - boxMin).cwiseMax(0.0f);
  for (int a = 0; a < 3; ++a) dims_[a] = std::max(1, static_cast<int>(std::ceil(extent[a] * inverseCellSize_)));
  const double cells = double(dims_.x()) * dims_.y() * dims_.z();
  if (cells > 4.0e8) throw std::invalid_argument("neighbour grid: container too large for the support radius");
  cellStart_.assign(size_t(cells) + 1, 0);
}

uint32_t NeighborGrid::cellIndex(float x, float y, float z) const {
  auto clampCell = [](float v, int n) { return std::clamp(static_cast<int>(std::floor(v)), 0, n - 1); };
  const int i = clampCell((x - origin_.x()) * inverseCellSize_, dims_.x());
  const int j = clampCell((y - origin_.y()) * inverseCellSize_, dims_.y());
  const int k = clampCell((z - origin_.z()) * inverseCellSize_, dims_.z());
  return uint32_t((k * dims_.y() + j) * dims_.x() + i);
}

void NeighborGrid::sort(const float* x, const float* y, const float* z, size_t count, std::vector<uint32_t>& order) {
  cellOf_.resize(count);
  sortedCell_.resize(count);
  order.resize(count);
  std::fill(cellStart_.begin(), cellStart_.end(), 0u);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, count, 16384), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) cellOf_[i] = cellIndex(x[i], y[i], z[i]);
  });
  // The histogram, prefix sum and scatter stay serial: a stable order independent of threads.
  for (size_t i = 0; i < count; ++i) ++cellStart_[cellOf_[i] + 1];
  for (size_t c = 1; c < cellStart_.size(); ++c) cellStart_[c] += cellStart_[c - 1];
  // Stable counting sort: particles keep their previous relative order inside a cell, so the
  // order (and every sum over it) is a deterministic function of the previous state.
  for (size_t i = 0; i < count; ++i) {
    const uint32_t slot = cellStart_[cellOf_[i]]++;
    order[slot] = uint32_t(i);
  }
  // The increments above shifted each start to the next cell's start: shift back.
  for (size_t c = cellStart_.size() - 1; c > 0; --c) cellStart_[c] = cellStart_[c - 1];
  cellStart_[0] = 0;
  tbb::parallel_for(tbb::blocked_range<size_t>(0, count, 16384), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t k = r.begin(); k != r.end(); ++k) sortedCell_[k] = cellOf_[order[k]];
  });
}

int NeighborGrid::candidateRanges(uint32_t cell, std::array<std::array<uint32_t, 2>, 9>& ranges) const {
  const int nx = dims_.x(), ny = dims_.y(), nz = dims_.z();
  const int i = int(cell % uint32_t(nx));
  const int j = int((cell / uint32_t(nx)) % uint32_t(ny));
  const int k = int(cell / uint32_t(nx * ny));
  const int i0 = std::max(i - 1, 0), i1 = std::min(i + 1, nx - 1);
  int n = 0;
  for (int kk = std::max(k - 1, 0); kk <= std::min(k + 1, nz - 1); ++kk)
    for (int jj = std::max(j - 1, 0); jj <= std::min(j + 1, ny - 1); ++jj) {
      const uint32_t row = uint32_t((kk * ny + jj) * nx);
      const uint32_t begin = cellStart_[row + uint32_t(i0)];
      const uint32_t end = cellStart_[row + uint32_t(i1) + 1];
      if (begin < end) ranges[n++] = {begin, end};
    }
  return n;
}

void NeighborLists::resize(size_t particles) {
  chunks_.resize((particles + kChunk - 1) / kChunk);
  scratch_.resize(chunks_.size());
  slopes_.resize(chunks_.size());
  begin_.resize(particles);
  end_.resize(particles);
}

size_t NeighborLists::totalCount() const {
  size_t total = 0;
  for (size_t i = 0; i < begin_.size(); ++i) total += end_[i] - begin_[i];
  return total;
}

size_t NeighborLists::memoryBytes() const {
  size_t bytes = (begin_.capacity() + end_.capacity()) * sizeof(uint32_t);
  for (const auto& c : chunks_) bytes += c.capacity() * sizeof(uint32_t);
  for (const auto& c : scratch_) bytes += c.capacity() * sizeof(uint32_t);
  for (const auto& c : slopes_) bytes += c.capacity() * sizeof(float);
  return bytes;
}

}  // namespace kurage::sim
