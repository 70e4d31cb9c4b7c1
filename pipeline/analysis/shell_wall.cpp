#include "pipeline/analysis/shell_wall.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>

namespace kurage::pipeline {

ShellWall::ShellWall(const sim::BodyParams& shell, int kind, const sim::ParticleSet& p, float fluidSpacing)
    : kind_(kind), layers_(std::max(1, shell.layers)), spacing_(shell.spacingMetres(fluidSpacing)),
      axis_(shell.axis.cast<double>().normalized()) {
  const Eigen::Vector3d centre = shell.center.cast<double>();
  const double rimPolar = double(shell.openingAngle) * std::numbers::pi / 180.0;
  struct Entry {
    int64_t id;
    int8_t layer;
    uint8_t margin;
    Eigen::Vector3d at;
  };
  std::vector<Entry> entries;
  for (size_t i = 0; i < p.size(); ++i) {
    if (p.kind[i] != kind) continue;
    const Eigen::Vector3d d = Eigen::Vector3d(p.x[i], p.y[i], p.z[i]) - centre;
    const double r = d.norm();
    const int layer = std::clamp(int(std::lround((r - shell.innerRadius) / spacing_)), 0, layers_ - 1);
    const double polar = std::acos(std::clamp(d.dot(axis_) / std::max(r, 1e-12), -1.0, 1.0));
    entries.push_back({p.id[i], int8_t(layer), uint8_t(polar >= rimPolar - 0.25 * spacing_ / shell.innerRadius),
                       Eigen::Vector3d(p.x[i], p.y[i], p.z[i])});
  }
  std::sort(entries.begin(), entries.end(), [](const Entry& a, const Entry& b) { return a.id < b.id; });
  for (const Entry& e : entries) {
    sortedIds_.push_back(e.id);
    layer_.push_back(e.layer);
    margin_.push_back(e.margin);
    built_.push_back(e.at);
  }
}

double ShellWall::apexHeight(const sim::ParticleSet& p) const {
  double top = -std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < p.size(); ++i)
    if (p.kind[i] == kind_) top = std::max(top, double(p.z[i]));
  return top;
}

ShellWall::Shape ShellWall::shape(const sim::ParticleSet& p) const {
  Eigen::Vector3d margin = Eigen::Vector3d::Zero();
  std::vector<Eigen::Vector3d> points;
  size_t n = 0;
  for (size_t i = 0; i < p.size(); ++i) {
    if (p.kind[i] != kind_) continue;
    points.emplace_back(p.x[i], p.y[i], p.z[i]);
    const int k = indexOf(p.id[i]);
    if (k < 0 || !margin_[size_t(k)]) continue;
    margin += points.back();
    ++n;
  }
  Shape s;
  if (n == 0) return s;
  margin /= double(n);
  Eigen::Vector3d axis = centre(p) - margin;
  axis = axis.norm() > 0.0 ? Eigen::Vector3d(axis.normalized()) : axis_;
  double lo = std::numeric_limits<double>::infinity(), hi = -lo, wide = 0.0;
  for (const Eigen::Vector3d& x : points) {
    const Eigen::Vector3d d = x - margin;
    const double along = d.dot(axis);
    lo = std::min(lo, along);
    hi = std::max(hi, along);
    wide = std::max(wide, (d - along * axis).norm());
  }
  s.height = hi - lo;
  s.diameter = 2.0 * wide;
  return s;
}

double ShellWall::closestUnjoinedPair(const sim::ParticleSet& p, double joinedWithin) const {
  std::vector<std::pair<size_t, Eigen::Vector3d>> now;  // (position in sortedIds_, position)
  for (size_t i = 0; i < p.size(); ++i) {
    if (p.kind[i] != kind_) continue;
    const int k = indexOf(p.id[i]);
    if (k >= 0) now.emplace_back(size_t(k), Eigen::Vector3d(p.x[i], p.y[i], p.z[i]));
  }
  double closest = std::numeric_limits<double>::infinity();
  const double joined2 = joinedWithin * joinedWithin;
  for (size_t a = 0; a < now.size(); ++a)
    for (size_t b = a + 1; b < now.size(); ++b) {
      if ((built_[now[a].first] - built_[now[b].first]).squaredNorm() < joined2) continue;
      closest = std::min(closest, (now[a].second - now[b].second).norm());
    }
  return closest;
}

int ShellWall::indexOf(int64_t id) const {
  const auto it = std::lower_bound(sortedIds_.begin(), sortedIds_.end(), id);
  return it != sortedIds_.end() && *it == id ? int(it - sortedIds_.begin()) : -1;
}

Eigen::Vector3d ShellWall::centre(const sim::ParticleSet& p) const {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  double mass = 0.0;
  for (size_t i = 0; i < p.size(); ++i)
    if (p.kind[i] == kind_) {
      sum += double(p.mass[i]) * Eigen::Vector3d(p.x[i], p.y[i], p.z[i]);
      mass += double(p.mass[i]);
    }
  return mass > 0.0 ? Eigen::Vector3d(sum / mass) : sum;
}

double ShellWall::marginRadius(const sim::ParticleSet& p) const {
  // The margin's own centroid, so that a tilted bell keeps its margin radius.
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  std::vector<Eigen::Vector3d> ring;
  for (size_t i = 0; i < p.size(); ++i) {
    if (p.kind[i] != kind_) continue;
    const int k = indexOf(p.id[i]);
    if (k < 0 || !margin_[size_t(k)]) continue;
    ring.emplace_back(p.x[i], p.y[i], p.z[i]);
    c += ring.back();
  }
  if (ring.empty()) return 0.0;
  c /= double(ring.size());
  double sum = 0.0;
  for (const Eigen::Vector3d& x : ring) sum += (x - c).norm();
  return sum / double(ring.size());
}

double ShellWall::tiltDegrees(const sim::ParticleSet& p) const { return tiltDegrees(p, axis_); }

double ShellWall::tiltDegrees(const sim::ParticleSet& p, const Eigen::Vector3d& reference) const {
  Eigen::Vector3d margin = Eigen::Vector3d::Zero();
  size_t n = 0;
  for (size_t i = 0; i < p.size(); ++i) {
    if (p.kind[i] != kind_) continue;
    const int k = indexOf(p.id[i]);
    if (k < 0 || !margin_[size_t(k)]) continue;
    margin += Eigen::Vector3d(p.x[i], p.y[i], p.z[i]);
    ++n;
  }
  if (n == 0) return 0.0;
  const Eigen::Vector3d up = centre(p) - margin / double(n);
  if (!(up.norm() > 0.0)) return 0.0;
  return std::acos(std::clamp(up.normalized().dot(reference.normalized()), -1.0, 1.0)) * 180.0 / std::numbers::pi;
}

size_t ShellWall::fluidInsideWall(const sim::ParticleSet& p) const {
  if (layers_ < 2) return 0;
  // The innermost and outermost layers' particles in buckets of one spacing.
  const float cell = spacing_;
  const auto key = [cell](float x, float y, float z) {
    const auto c = [cell](float v) { return uint64_t(int64_t(std::floor(v / cell)) & 0x1fffff); };
    return (c(x) << 42) | (c(y) << 21) | c(z);
  };
  std::map<uint64_t, std::vector<std::pair<Eigen::Vector3f, int8_t>>> buckets;
  for (size_t i = 0; i < p.size(); ++i) {
    if (p.kind[i] != kind_) continue;
    const int k = indexOf(p.id[i]);
    if (k < 0) continue;
    const int8_t layer = layer_[size_t(k)];
    if (layer != 0 && layer != layers_ - 1) continue;
    buckets[key(p.x[i], p.y[i], p.z[i])].push_back({Eigen::Vector3f(p.x[i], p.y[i], p.z[i]), layer});
  }
  const float reach2 = spacing_ * spacing_;
  std::vector<Eigen::Vector3f> near[2];
  size_t inside = 0;
  for (size_t i = 0; i < p.size(); ++i) {
    if (p.kind[i] != 0) continue;
    const Eigen::Vector3f x(p.x[i], p.y[i], p.z[i]);
    near[0].clear();
    near[1].clear();
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const auto it = buckets.find(key(x.x() + dx * cell, x.y() + dy * cell, x.z() + dz * cell));
          if (it == buckets.end()) continue;
          for (const auto& [q, layer] : it->second)
            if ((q - x).squaredNorm() < reach2) near[layer == 0 ? 0 : 1].push_back(q - x);
        }
    // Between the layers: an inner and an outer particle on opposite sides of it.
    bool between = false;
    for (const Eigen::Vector3f& a : near[0])
      for (const Eigen::Vector3f& b : near[1]) between = between || a.dot(b) < 0.0f;
    inside += between;
  }
  return inside;
}

}  // namespace kurage::pipeline
