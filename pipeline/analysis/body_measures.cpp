#include "pipeline/analysis/body_measures.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <vector>

namespace kurage::pipeline {

KindExtent kindExtent(const sim::ParticleSet& p, int kind) {
  KindExtent e;
  for (size_t i = 0; i < p.size(); ++i)
    if (p.kind[i] == kind) {
      const Eigen::Vector3f x(p.x[i], p.y[i], p.z[i]);
      e.min = e.min.cwiseMin(x);
      e.max = e.max.cwiseMax(x);
      e.centre += x.cast<double>();
      ++e.count;
    }
  if (e.count) e.centre /= double(e.count);
  return e;
}

double freeSurfaceHeight(const sim::ParticleSet& p, double cx, double cy, double clear, float cellSize, float spacing) {
  std::map<std::pair<int, int>, float> top;
  for (size_t i = 0; i < p.size(); ++i) {
    if (p.kind[i] != 0) continue;
    const int cellX = int(std::floor(p.x[i] / cellSize)), cellY = int(std::floor(p.y[i] / cellSize));
    const double mx = (cellX + 0.5) * cellSize, my = (cellY + 0.5) * cellSize;
    if (std::hypot(mx - cx, my - cy) <= clear) continue;
    const auto key = std::make_pair(cellX, cellY);
    const auto it = top.find(key);
    if (it == top.end() || it->second < p.z[i]) top[key] = p.z[i];
  }
  double sum = 0.0;
  for (const auto& [key, z] : top) sum += z;
  return top.empty() ? 0.0 : sum / double(top.size()) + 0.5 * spacing;
}

double submergedFraction(const sim::ParticleSet& p, int kind, float fluidSpacing) {
  const KindExtent e = kindExtent(p, kind);
  if (e.count == 0) return 0.0;
  const double halfExtent = 0.5 * std::max(e.max.x() - e.min.x(), e.max.y() - e.min.y());
  const double surface =
      freeSurfaceHeight(p, e.centre.x(), e.centre.y(), halfExtent + 1.5 * fluidSpacing, fluidSpacing, fluidSpacing);
  size_t below = 0;
  for (size_t i = 0; i < p.size(); ++i) below += p.kind[i] == kind && p.z[i] < surface;
  return double(below) / double(e.count);
}

double rmsSpeed(const sim::ParticleSet& p, int kind) {
  double v2 = 0.0;
  size_t n = 0;
  for (size_t i = 0; i < p.size(); ++i)
    if (p.kind[i] == kind) {
      v2 += p.vx[i] * p.vx[i] + p.vy[i] * p.vy[i] + p.vz[i] * p.vz[i];
      ++n;
    }
  return n == 0 ? 0.0 : std::sqrt(v2 / double(n));
}

MembraneLeak membraneLeak(const sim::ParticleSet& p, int kind, float fluidSpacing) {
  const float lowest = kindExtent(p, kind).min.z();
  MembraneLeak m;
  for (size_t i = 0; i < p.size(); ++i)
    if (p.kind[i] == 0) {
      ++m.fluid;
      m.leaked += p.z[i] < lowest - 0.5f * fluidSpacing;
    }
  return m;
}

MembraneLoad membraneLoad(const sim::ParticleSet& p, int kind, float supportRadius) {
  const float near = 0.7f * supportRadius;
  std::vector<size_t> fluid, sheet;
  for (size_t i = 0; i < p.size(); ++i) {
    if (p.kind[i] == 0) fluid.push_back(i);
    else if (p.kind[i] == kind) sheet.push_back(i);
  }
  auto d2 = [&](size_t i, size_t j) {
    const float dx = p.x[i] - p.x[j], dy = p.y[i] - p.y[j], dz = p.z[i] - p.z[j];
    return dx * dx + dy * dy + dz * dz;
  };
  std::vector<double> sheetPressure, fluidPressure;
  for (size_t j : sheet)
    if (std::any_of(fluid.begin(), fluid.end(), [&](size_t i) { return d2(i, j) < near * near; }))
      sheetPressure.push_back(p.pressure[j]);
  for (size_t i : fluid)
    if (std::any_of(sheet.begin(), sheet.end(), [&](size_t j) { return d2(i, j) < supportRadius * supportRadius; }))
      fluidPressure.push_back(p.pressure[i]);
  auto quantile = [](std::vector<double>& v, double q) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    return v[size_t(q * double(v.size() - 1))];
  };
  MembraneLoad m;
  m.sheetParticles = sheetPressure.size();
  m.fluidParticles = fluidPressure.size();
  m.sheetPressure90 = quantile(sheetPressure, 0.9);
  m.fluidPressure50 = quantile(fluidPressure, 0.5);
  return m;
}

namespace {
// Distance between the segments [p0, p1] and [q0, q1] (clamped closest points; Ericson 2005, 5.1.9).
double segmentDistance(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1, const Eigen::Vector3d& q0,
                       const Eigen::Vector3d& q1) {
  const Eigen::Vector3d d1 = p1 - p0, d2 = q1 - q0, r = p0 - q0;
  const double a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r);
  double s = 0.0, t = 0.0;
  if (a <= 1e-18 && e <= 1e-18) return r.norm();
  if (a <= 1e-18) {
    t = std::clamp(f / e, 0.0, 1.0);
  } else {
    const double c = d1.dot(r);
    if (e <= 1e-18) {
      s = std::clamp(-c / a, 0.0, 1.0);
    } else {
      const double b = d1.dot(d2), denom = a * e - b * b;
      s = denom > 1e-18 ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
      t = (b * s + f) / e;
      if (t < 0.0) {
        t = 0.0;
        s = std::clamp(-c / a, 0.0, 1.0);
      } else if (t > 1.0) {
        t = 1.0;
        s = std::clamp((b - c) / a, 0.0, 1.0);
      }
    }
  }
  return ((p0 + s * d1) - (q0 + t * d2)).norm();
}
}  // namespace

double chainSelfApproach(const sim::ParticleSet& p, int kind) {
  std::vector<std::pair<int64_t, Eigen::Vector3d>> chain;
  for (size_t i = 0; i < p.size(); ++i)
    if (p.kind[i] == kind) chain.emplace_back(p.id[i], Eigen::Vector3d(p.x[i], p.y[i], p.z[i]));
  std::sort(chain.begin(), chain.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  double closest = std::numeric_limits<double>::infinity();
  for (size_t a = 0; a + 1 < chain.size(); ++a)
    for (size_t b = a + 2; b + 1 < chain.size(); ++b)
      closest = std::min(closest, segmentDistance(chain[a].second, chain[a + 1].second, chain[b].second,
                                                  chain[b + 1].second));
  return closest;
}

}  // namespace kurage::pipeline
