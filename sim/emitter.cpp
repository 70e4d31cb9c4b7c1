#include "sim/emitter.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace kurage::sim {

std::vector<Eigen::Vector3f> discPattern(int count, float radius, const Eigen::Vector3f& u, const Eigen::Vector3f& v) {
  std::vector<Eigen::Vector3f> points;
  points.reserve(size_t(std::max(count, 0)));
  const double golden = std::numbers::pi * (3.0 - std::sqrt(5.0));
  for (int k = 0; k < count; ++k) {
    const double r = radius * std::sqrt((k + 0.5) / count);
    const double a = k * golden;
    points.push_back(float(r * std::cos(a)) * u + float(r * std::sin(a)) * v);
  }
  return points;
}

Emitter::Emitter(const EmitterParams& params, float spacing) : params_(params), spacing_(spacing) {
  direction_ = params.direction.normalized();
  // Any unit vector not parallel to the direction gives the disc's plane.
  const Eigen::Vector3f helper = std::fabs(direction_.x()) < 0.9f ? Eigen::Vector3f::UnitX() : Eigen::Vector3f::UnitY();
  u_ = direction_.cross(helper).normalized();
  v_ = direction_.cross(u_);
}

size_t Emitter::expectedTotal() const {
  const double area = std::numbers::pi * params_.radius * params_.radius;
  return size_t(std::ceil(area * params_.speed * (params_.end - params_.start) / std::pow(spacing_, 3))) + 1;
}

size_t Emitter::emit(double t, float dt, ParticleSet& particles, float mass, float restDensity, int64_t& nextId) {
  // The part of the step during which the nozzle was open.
  const double open = std::min(t, double(params_.end)) - std::max(t - dt, double(params_.start));
  if (open <= 0.0) return 0;
  const double l = spacing_;
  const double area = std::numbers::pi * params_.radius * params_.radius;
  travelled_ += params_.speed * open;
  // The nozzle closes during this step: the last layer, if more than half of it has left, goes too
  // (so the layers' count is speed x time / l rounded, not cut).
  const bool closing = t >= double(params_.end) && t - dt < double(params_.end);
  size_t spawned = 0;
  while (travelled_ >= l || (closing && travelled_ >= 0.5 * l)) {
    travelled_ = std::max(travelled_ - l, 0.0);
    // This layer left the nozzle plane `travelled_` ago (in distance): place it there.
    const Eigen::Vector3f centre = params_.position + float(travelled_) * direction_;
    emittedTarget_ += area * l / (l * l * l);  // one layer carries area x l of fluid
    const int count = int(std::llround(emittedTarget_)) - int(emitted_);
    if (count <= 0) continue;
    emitted_ += size_t(count);
    const Eigen::Vector3f velocity = params_.speed * direction_;
    const float clearance2 = float(0.25 * l * l);
    const float reach = params_.radius + float(l);
    // Existing particles near the nozzle (a linear scan: layers are rare compared with steps).
    std::vector<Eigen::Vector3f> nearby;
    for (size_t i = 0; i < particles.size(); ++i) {
      const Eigen::Vector3f p(particles.x[i], particles.y[i], particles.z[i]);
      if ((p - centre).squaredNorm() < reach * reach) nearby.push_back(p);
    }
    for (const Eigen::Vector3f& offset : discPattern(count, params_.radius, u_, v_)) {
      const Eigen::Vector3f p = centre + offset;
      const bool occupied = std::any_of(nearby.begin(), nearby.end(),
                                        [&](const Eigen::Vector3f& q) { return (q - p).squaredNorm() < clearance2; });
      if (occupied) {
        ++blocked_;
        continue;
      }
      particles.add(p.x(), p.y(), p.z(), velocity.x(), velocity.y(), velocity.z(), restDensity, mass, nextId++, 0);
      ++spawned;
    }
  }
  return spawned;
}

size_t applySink(const SinkParams& sink, ParticleSet& particles, std::vector<uint8_t>& flags) {
  const size_t n = particles.size();
  flags.assign(n, 0);
  size_t removed = 0;
  for (size_t i = 0; i < n; ++i) {
    const bool inside = particles.kind[i] == 0 && particles.x[i] >= sink.min.x() && particles.x[i] <= sink.max.x() &&
                        particles.y[i] >= sink.min.y() && particles.y[i] <= sink.max.y() &&
                        particles.z[i] >= sink.min.z() && particles.z[i] <= sink.max.z();
    flags[i] = inside;
    removed += inside;
  }
  if (removed) particles.removeFlagged(flags);
  return removed;
}

void Emitter::saveState(StateWriter& out) const {
  out.value(travelled_);
  out.value(emittedTarget_);
  out.value(uint64_t(emitted_));
  out.value(uint64_t(blocked_));
}

void Emitter::restoreState(StateReader& in) {
  travelled_ = in.value<double>();
  emittedTarget_ = in.value<double>();
  emitted_ = size_t(in.value<uint64_t>());
  blocked_ = size_t(in.value<uint64_t>());
}

}  // namespace kurage::sim
