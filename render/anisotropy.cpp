// Anisotropic kernels (Yu & Turk 2013); see anisotropy.h for the method and its limits.
#include "render/anisotropy.h"

#include <Eigen/Eigenvalues>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
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

  const float inverseSquare = 1.0f / (radius * radius);
  std::vector<EllipsoidKernel> kernels(n);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 256), [&](const tbb::blocked_range<size_t>& range) {
    std::vector<std::pair<Eigen::Vector3d, double>> neighbours;  // (x_j, w_ij)
    for (size_t i = range.begin(); i != range.end(); ++i) {
      const Eigen::Vector3d xi = positions[i].cast<double>();
      int64_t c[3];
      for (int a = 0; a < 3; ++a) c[a] = int64_t(std::floor(xi[a] * invR));
      neighbours.clear();
      double weightSum = 0.0;
      Eigen::Vector3d weighted = Eigen::Vector3d::Zero();
      // The 27 cells around, in key order; within a cell, in index order (the sort's).
      for (int64_t dx = -1; dx <= 1; ++dx)
        for (int64_t dy = -1; dy <= 1; ++dy) {
          const uint64_t first = cellKey(c[0] + dx, c[1] + dy, c[2] - 1), last = cellKey(c[0] + dx, c[1] + dy, c[2] + 1);
          for (auto it = std::lower_bound(order.begin(), order.end(), std::make_pair(first, uint32_t(0)));
               it != order.end() && it->first <= last; ++it) {
            const Eigen::Vector3d xj = positions[it->second].cast<double>();
            const double distance = (xj - xi).norm() * invR;
            if (distance >= 1.0) continue;
            const double w = 1.0 - distance * distance * distance;  // w_ij
            neighbours.emplace_back(xj, w);
            weightSum += w;
            weighted += w * xj;
          }
        }
      const Eigen::Vector3d mean = weighted / weightSum;  // x_i^w (i itself has w = 1)
      EllipsoidKernel& kernel = kernels[i];
      kernel.centre = ((1.0 - params.smoothing) * xi + params.smoothing * mean).cast<float>();
      if (int(neighbours.size()) < params.minNeighbours) {
        kernel.shape = Eigen::Matrix3f::Identity() * inverseSquare;
        continue;
      }
      Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
      for (const auto& [xj, w] : neighbours) {
        const Eigen::Vector3d d = xj - mean;
        covariance += w * d * d.transpose();
      }
      covariance /= weightSum;
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen;
      eigen.computeDirect(covariance);
      const Eigen::Vector3d s = eigen.eigenvalues();  // ascending
      const double largest = s[2];
      if (!(largest > 0.0)) {  // every neighbour at one point
        kernel.shape = Eigen::Matrix3f::Identity() * inverseSquare;
        continue;
      }
      Eigen::Vector3d inverseRadius2;  // 1 / a_k^2, a_k = R s~_k / s~_1
      for (int k = 0; k < 3; ++k) {
        const double clamped = std::max(s[k], largest / double(params.maxStretch));
        const double a = double(radius) * clamped / largest;
        inverseRadius2[k] = 1.0 / (a * a);
      }
      const Eigen::Matrix3d& q = eigen.eigenvectors();
      const Eigen::Matrix3d m = q * inverseRadius2.asDiagonal() * q.transpose();
      kernel.shape = (0.5 * (m + m.transpose())).cast<float>();
    }
  });
  return kernels;
}

}  // namespace kurage::render
