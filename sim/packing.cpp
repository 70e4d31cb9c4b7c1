#include "sim/packing.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace kurage::sim {

namespace {

// W(r), W'(r) and W''(r) of the density kernel, support h (spacings).
struct KernelValues {
  DensityKernel kind;
  double h, sigma;
  KernelValues(DensityKernel k, double support)
      : kind(k), h(support),
        sigma(k == DensityKernel::CubicSpline ? 8.0 / (M_PI * support * support * support)
                                              : 315.0 / (64.0 * M_PI * std::pow(support, 9))) {}
  double value(double r) const {
    if (r >= h) return 0.0;
    if (kind == DensityKernel::Poly6) { const double t = h * h - r * r; return sigma * t * t * t; }
    const double q = r / h;
    if (q <= 0.5) return sigma * (6.0 * q * q * (q - 1.0) + 1.0);
    const double t = 1.0 - q;
    return sigma * 2.0 * t * t * t;
  }
  double first(double r) const {
    if (r >= h) return 0.0;
    if (kind == DensityKernel::Poly6) { const double t = h * h - r * r; return -6.0 * sigma * r * t * t; }
    const double q = r / h;
    if (q <= 0.5) return sigma / h * q * (18.0 * q - 12.0);
    const double t = 1.0 - q;
    return -6.0 * sigma / h * t * t;
  }
  double second(double r) const {
    if (r >= h) return 0.0;
    if (kind == DensityKernel::Poly6) { const double t = h * h - r * r; return -6.0 * sigma * t * (t - 4.0 * r * r); }
    const double q = r / h;
    if (q <= 0.5) return sigma / (h * h) * (36.0 * q - 12.0);
    return 12.0 * sigma / (h * h) * (1.0 - q);
  }
};

// SplitMix64: a fixed pseudo-random sequence (the tile must not depend on anything else).
uint64_t splitmix(uint64_t& state) {
  uint64_t z = (state += 0x9E3779B97F4A7C15ull);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

constexpr double kJitter = 0.3;   // the start: the cubic lattice moved by up to +-0.15 spacings
constexpr int kIterations = 200;  // descent steps (the sum settles to within 0.02 % in 150)
constexpr double kMaxMove = 0.1;  // the largest move of a point in one step, spacings

}  // namespace

int tileCells(float supportRatio) { return std::max(8, int(std::ceil(2.0 * double(supportRatio))) + 2); }

bool holdsTile(const FluidBlock& block, float spacing, float supportRatio) {
  return ((block.max - block.min).array() >= float(tileCells(supportRatio)) * spacing).all();
}

PackingTile relaxedTile(float supportRatio, DensityKernel kernel) {
  const double h = supportRatio;
  const KernelValues w(kernel, h);
  PackingTile tile;
  tile.cells = tileCells(supportRatio);
  const int n = tile.cells;
  const double edge = n;
  // The cubic lattice's kernel sum, and the mean diagonal of the Hessian of a point's sum (the
  // scale of the first step).
  const int reach = int(std::ceil(h));
  double latticeSum = 0.0, diagonal = 0.0;
  for (int k = -reach; k <= reach; ++k)
    for (int j = -reach; j <= reach; ++j)
      for (int i = -reach; i <= reach; ++i) {
        const double r = std::sqrt(double(i * i + j * j + k * k));
        latticeSum += w.value(r);
        if (r > 0.0) diagonal += (w.second(r) + 2.0 * w.first(r) / r) / 3.0;
      }
  tile.latticeKernelSum = latticeSum;
  std::vector<Eigen::Vector3d> x;
  uint64_t state = 0x6B75726167650001ull;
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        Eigen::Vector3d p(i + 0.5, j + 0.5, k + 0.5);
        for (int a = 0; a < 3; ++a) p[a] += kJitter * (double(splitmix(state) >> 11) * 0x1.0p-53 - 0.5);
        x.push_back(p);
      }
  const size_t count = x.size();
  // Pairs closer than h + skin with their periodic shift (x_a - x_b + shift is the minimum
  // image), rebuilt when a point has moved more than half the skin. Positions are not wrapped
  // while the lists hold, so the shifts stay valid.
  struct Pair {
    uint32_t a, b;
    Eigen::Vector3d shift;
  };
  const double skin = 0.5, listRadius2 = (h + skin) * (h + skin);
  std::vector<Pair> pairs;
  std::vector<Eigen::Vector3d> listed;
  auto build = [&]() {
    for (Eigen::Vector3d& p : x)
      for (int c = 0; c < 3; ++c) p[c] -= edge * std::floor(p[c] / edge);
    listed = x;
    pairs.clear();
    for (size_t a = 0; a < count; ++a)
      for (size_t b = a + 1; b < count; ++b) {
        const Eigen::Vector3d d = x[a] - x[b];
        Eigen::Vector3d shift;
        for (int c = 0; c < 3; ++c) shift[c] = -edge * std::round(d[c] / edge);
        if ((d + shift).squaredNorm() < listRadius2) pairs.push_back({uint32_t(a), uint32_t(b), shift});
      }
  };
  // sum_i sum_{j != i} W_ij over the points (the self terms are constant) and its gradient.
  auto evaluate = [&](const std::vector<Eigen::Vector3d>& p, std::vector<Eigen::Vector3d>& g) {
    double e = 0.0;
    for (Eigen::Vector3d& v : g) v.setZero();
    for (const Pair& q : pairs) {
      const Eigen::Vector3d d = p[q.a] - p[q.b] + q.shift;
      const double r = d.norm();
      if (r >= h) continue;
      e += 2.0 * w.value(r);
      if (r > 1e-9) {
        const Eigen::Vector3d f = (2.0 * w.first(r) / r) * d;
        g[q.a] += f;
        g[q.b] -= f;
      }
    }
    return e;
  };
  // Steepest descent; the step grows by a tenth after a step that lowers the sum, and a step that
  // would raise it is refused and halved. No point moves more than kMaxMove a step, so the lists,
  // rebuilt once a point is farther than half the skin less kMaxMove from where they were built,
  // hold every pair within h.
  build();
  std::vector<Eigen::Vector3d> gradient(count), trial(count), trialGradient(count);
  double energy = evaluate(x, gradient), step = 0.1 / std::fabs(diagonal);
  for (int it = 0; it < kIterations; ++it) {
    double drift2 = 0.0, largest2 = 0.0;
    for (size_t a = 0; a < count; ++a) {
      drift2 = std::max(drift2, (x[a] - listed[a]).squaredNorm());
      largest2 = std::max(largest2, gradient[a].squaredNorm());
    }
    if (std::sqrt(drift2) > 0.5 * skin - kMaxMove) {
      build();
      energy = evaluate(x, gradient);
    }
    step = std::min(step, kMaxMove / std::max(std::sqrt(largest2), 1e-300));
    for (size_t a = 0; a < count; ++a) trial[a] = x[a] - step * gradient[a];
    const double trialEnergy = evaluate(trial, trialGradient);
    if (trialEnergy < energy) {
      x.swap(trial);
      gradient.swap(trialGradient);
      energy = trialEnergy;
      step *= 1.1;
    } else {
      step *= 0.5;
    }
  }
  build();
  std::vector<double> sums(count, w.value(0.0));
  for (const Pair& q : pairs) {
    const double v = w.value((x[q.a] - x[q.b] + q.shift).norm());
    sums[q.a] += v;
    sums[q.b] += v;
  }
  double total = 0.0;
  for (double s : sums) total += s;
  tile.kernelSum = total / double(count);
  for (const Eigen::Vector3d& p : x) tile.points.push_back(p.cast<float>());
  return tile;
}

std::vector<Eigen::Vector3f> tiledPoints(const FluidBlock& block, float spacing, const PackingTile& tile) {
  std::vector<Eigen::Vector3f> points;
  const Eigen::Vector3f extent = block.max - block.min;
  const float edge = float(tile.cells) * spacing;
  Eigen::Vector3i repeats;
  for (int a = 0; a < 3; ++a) repeats[a] = std::max(0, int(std::ceil(extent[a] / edge)));
  for (int k = 0; k < repeats.z(); ++k)
    for (int j = 0; j < repeats.y(); ++j)
      for (int i = 0; i < repeats.x(); ++i)
        for (const Eigen::Vector3f& q : tile.points) {
          const Eigen::Vector3f p = block.min + spacing * q + edge * Eigen::Vector3f(float(i), float(j), float(k));
          if ((p.array() >= block.min.array()).all() && (p.array() < block.max.array()).all()) points.push_back(p);
        }
  return points;
}

float tileParticleMass(const PackingTile& tile, float spacing, float restDensity) {
  // kernelSum is per spacing^3 (the tile's kernels have h in spacings): sum in metres^-3 = S / l^3.
  return float(double(restDensity) * std::pow(double(spacing), 3) / tile.kernelSum);
}

}  // namespace kurage::sim
