// Anisotropic kernels (Yu & Turk 2013); see anisotropy.h for the method and its limits.
#include "render/anisotropy.h"

#include <Eigen/Eigenvalues>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <utility>

namespace kurage::render {

namespace {

constexpr int kCellBits = 21;
constexpr int64_t kCellLimit = int64_t(1) << (kCellBits - 1);

// A grid cell's coordinates packed into a key ordered lexicographically by (x, y, z).
uint64_t cellKey(int64_t x, int64_t y, int64_t z) {
  const auto u = [](int64_t v) { return static_cast<uint64_t>(v + kCellLimit); };
  return (u(x) << (2 * kCellBits)) | (u(y) << kCellBits) | u(z);
}

}  // namespace

std::vector<EllipsoidKernel> anisotropicKernels(const std::vector<Eigen::Vector3f>& positions, float radius,
                                                const AnisotropyParams& params) {
  if (!(std::isfinite(radius) && radius > 0.0f && std::isfinite(params.neighbourRadius) &&
        params.neighbourRadius > 0.0f && params.maxStretch >= 1.0f && std::isfinite(params.maxStretch) &&
        params.smoothing >= 0.0f && params.smoothing <= 1.0f)) {
    throw std::invalid_argument("anisotropic kernels: parameters out of range (need radius, neighbour radius > 0, "
                                "max stretch >= 1, 0 <= smoothing <= 1)");
  }
  const size_t n = positions.size();
  const double r = double(params.neighbourRadius) * radius;  // neighbourhood radius, metres
  const double invR = 1.0 / r;

  // Particles sorted by the cell (of size r) that holds them.
  std::vector<std::pair<uint64_t, uint32_t>> order(n);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 4096), [&](const tbb::blocked_range<size_t>& range) {
    for (size_t i = range.begin(); i != range.end(); ++i) {
      int64_t c[3];
      for (int a = 0; a < 3; ++a) {
        const double q = std::floor(double(positions[i][a]) * invR);
        if (!(std::abs(q) < double(kCellLimit - 2))) {
          throw std::invalid_argument("anisotropic kernels: particle position not finite or too far from the origin");
        }
        c[a] = int64_t(q);
      }
      order[i] = {cellKey(c[0], c[1], c[2]), uint32_t(i)};
    }
  });
  tbb::parallel_sort(order.begin(), order.end());

  // Positions in cell order (contiguous for the neighbour loops) and the cells' ranges.
  std::vector<Eigen::Vector3f> sorted(n);
  std::vector<uint64_t> cellKeys;
  std::vector<size_t> cellBegin;  // cellBegin[c] .. cellBegin[c + 1]
  for (size_t k = 0; k < n; ++k) {
    sorted[k] = positions[order[k].second];
    if (k == 0 || order[k].first != order[k - 1].first) {
      cellKeys.push_back(order[k].first);
      cellBegin.push_back(k);
    }
  }
  cellBegin.push_back(n);

  const float inverseSquare = 1.0f / (radius * radius);
  const double r2 = r * r;
  std::vector<EllipsoidKernel> kernels(n);
  // Per cell: the particles of the 27 cells around it, as 9 contiguous ranges (the z-columns of
  // cells, in key order); every particle's sums run over them in that fixed order.
  tbb::parallel_for(tbb::blocked_range<size_t>(0, cellKeys.size(), 16), [&](const tbb::blocked_range<size_t>& range) {
    for (size_t cell = range.begin(); cell != range.end(); ++cell) {
      const uint64_t key = cellKeys[cell];
      const uint64_t mask = (uint64_t(1) << kCellBits) - 1;
      const int64_t cx = int64_t((key >> (2 * kCellBits)) & mask) - kCellLimit;
      const int64_t cy = int64_t((key >> kCellBits) & mask) - kCellLimit;
      const int64_t cz = int64_t(key & mask) - kCellLimit;
      std::array<std::pair<size_t, size_t>, 9> columns;
      int columnCount = 0;
      for (int64_t dx = -1; dx <= 1; ++dx)
        for (int64_t dy = -1; dy <= 1; ++dy) {
          const auto first = std::lower_bound(cellKeys.begin(), cellKeys.end(), cellKey(cx + dx, cy + dy, cz - 1));
          const auto last = std::upper_bound(first, cellKeys.end(), cellKey(cx + dx, cy + dy, cz + 1));
          if (first == last) continue;
          columns[size_t(columnCount++)] = {cellBegin[size_t(first - cellKeys.begin())],
                                            cellBegin[size_t(last - cellKeys.begin())]};
        }
      for (size_t k = cellBegin[cell]; k < cellBegin[cell + 1]; ++k) {
        const Eigen::Vector3d xi = sorted[k].cast<double>();
        // Sums over the neighbours of w, w d and w d d^T with d = x_j - x_i (relative, so that the
        // covariance C = sum w d d^T / W - m m^T, m = sum w d / W, keeps its precision).
        double weightSum = 0.0;
        Eigen::Vector3d first = Eigen::Vector3d::Zero();
        Eigen::Matrix3d second = Eigen::Matrix3d::Zero();
        int count = 0;
        double nearest2 = r2;  // squared distance to the nearest other particle
        for (int c = 0; c < columnCount; ++c)
          for (size_t j = columns[size_t(c)].first; j < columns[size_t(c)].second; ++j) {
            const Eigen::Vector3d d = sorted[j].cast<double>() - xi;
            const double d2 = d.squaredNorm();
            if (d2 >= r2) continue;
            if (d2 > 0.0) nearest2 = std::min(nearest2, d2);
            const double q = std::sqrt(d2) * invR;
            const double w = 1.0 - q * q * q;  // w_ij
            weightSum += w;
            first += w * d;
            second.noalias() += w * d * d.transpose();
            ++count;
          }
        const Eigen::Vector3d offset = first / weightSum;  // x_i^w - x_i (i itself has w = 1)
        EllipsoidKernel& kernel = kernels[order[k].second];
        kernel.centre = (xi + double(params.smoothing) * offset).cast<float>();
        if (count < params.minNeighbours) {
          kernel.shape = Eigen::Matrix3f::Identity() * inverseSquare;
          continue;
        }
        const Eigen::Matrix3d covariance = second / weightSum - offset * offset.transpose();
        Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen;
        eigen.computeDirect(covariance);
        const Eigen::Vector3d s = eigen.eigenvalues();  // ascending
        const double largest = s[2];
        if (!(largest > 0.0)) {  // every neighbour at one point
          kernel.shape = Eigen::Matrix3f::Identity() * inverseSquare;
          continue;
        }
        // 1 / a_k^2, a_k = max(R s~_k / s~_1, min(d_i, R)) (anisotropy.h).
        const double spacing = std::min(std::sqrt(nearest2), double(radius));
        Eigen::Vector3d inverseRadius2;
        for (int a = 0; a < 3; ++a) {
          const double clamped = std::max(s[a], largest / double(params.maxStretch));
          const double axis = std::max(double(radius) * clamped / largest, spacing);
          inverseRadius2[a] = 1.0 / (axis * axis);
        }
        const Eigen::Matrix3d& q = eigen.eigenvectors();
        const Eigen::Matrix3d m = q * inverseRadius2.asDiagonal() * q.transpose();
        kernel.shape = (0.5 * (m + m.transpose())).cast<float>();
      }
    }
  });
  return kernels;
}

}  // namespace kurage::render
