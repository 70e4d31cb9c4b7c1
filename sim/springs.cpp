#include "sim/springs.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <numeric>
#include <stdexcept>

namespace kurage::sim {

std::vector<SpringPair> springPairsWithin(const std::vector<Eigen::Vector3f>& positions,
                                          const std::vector<int64_t>& ids, float radius, uint16_t group) {
  if (positions.size() != ids.size()) throw std::invalid_argument("springs: positions and ids differ in length");
  // Sweep along x: candidates of k are the particles after it in x order within `radius`.
  std::vector<uint32_t> order(positions.size());
  std::iota(order.begin(), order.end(), 0u);
  std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) {
    return positions[a].x() < positions[b].x() || (positions[a].x() == positions[b].x() && ids[a] < ids[b]);
  });
  std::vector<SpringPair> pairs;
  for (size_t s = 0; s < order.size(); ++s)
    for (size_t t = s + 1; t < order.size(); ++t) {
      const Eigen::Vector3f& p = positions[order[s]];
      const Eigen::Vector3f& q = positions[order[t]];
      if (q.x() - p.x() >= radius) break;
      const float length = (q - p).norm();
      if (length < radius && length > 0.0f) pairs.push_back({ids[order[s]], ids[order[t]], length, group, 0});
    }
  return pairs;
}

SpringNetwork SpringNetwork::connect(const std::vector<Eigen::Vector3f>& positions, const std::vector<int64_t>& ids,
                                     float radius) {
  return fromPairs(springPairsWithin(positions, ids, radius));
}

SpringNetwork SpringNetwork::fromPairs(const std::vector<SpringPair>& pairs) {
  SpringNetwork net;
  if (pairs.empty()) return net;
  int64_t lo = pairs[0].a, hi = pairs[0].a;
  for (const SpringPair& p : pairs) {
    lo = std::min({lo, p.a, p.b});
    hi = std::max({hi, p.a, p.b});
  }
  if (lo < 0 || hi >= int64_t(UINT32_MAX)) throw std::invalid_argument("springs: particle ids out of range");
  net.firstId_ = lo;
  const int64_t span = hi - lo + 1;
  // Both ends of every spring, grouped by id, each group sorted by the other id (a fixed order).
  std::vector<uint32_t> counts(size_t(span) + 1, 0);
  for (const SpringPair& p : pairs) {
    ++counts[size_t(p.a - lo) + 1];
    ++counts[size_t(p.b - lo) + 1];
  }
  std::partial_sum(counts.begin(), counts.end(), counts.begin());
  net.offsets_ = counts;
  net.ends_.resize(pairs.size() * 2);
  std::vector<uint32_t> cursor(counts.begin(), counts.end() - 1);
  for (const SpringPair& p : pairs) {
    net.ends_[cursor[size_t(p.a - lo)]++] = {uint32_t(p.b), p.restLength, p.group, p.muscles};
    net.ends_[cursor[size_t(p.b - lo)]++] = {uint32_t(p.a), p.restLength, p.group, p.muscles};
  }
  for (size_t k = 0; k + 1 < net.offsets_.size(); ++k)
    std::sort(net.ends_.begin() + net.offsets_[k], net.ends_.begin() + net.offsets_[k + 1],
              [](const End& x, const End& y) { return x.other < y.other; });
  return net;
}

bool SpringNetwork::connected(int64_t a, int64_t b) const {
  const End* first = begin(a);
  const End* last = end(a);
  if (first == last || b < 0) return false;
  const End* it = std::lower_bound(first, last, uint32_t(b), [](const End& e, uint32_t id) { return e.other < id; });
  return it != last && it->other == uint32_t(b);
}

const SpringNetwork::End* SpringNetwork::begin(int64_t id) const {
  const int64_t k = id - firstId_;
  if (k < 0 || k + 1 >= int64_t(offsets_.size())) return nullptr;
  return ends_.data() + offsets_[size_t(k)];
}

const SpringNetwork::End* SpringNetwork::end(int64_t id) const {
  const int64_t k = id - firstId_;
  if (k < 0 || k + 1 >= int64_t(offsets_.size())) return nullptr;
  return ends_.data() + offsets_[size_t(k) + 1];
}

void indexParticlesById(const ParticleSet& particles, std::vector<uint32_t>& index) {
  int64_t maxId = -1;
  for (int64_t id : particles.id) maxId = std::max(maxId, id);
  index.assign(size_t(maxId + 1), UINT32_MAX);
  for (size_t i = 0; i < particles.size(); ++i) index[size_t(particles.id[i])] = uint32_t(i);
}

void addSpringAccelerations(const SpringNetwork& springs, float stiffness, float damping, float dt,
                            ParticleSet& p, const std::vector<uint32_t>& indexOfId) {
  addSpringAccelerations(springs, std::vector<SpringGroup>{{stiffness, damping}}, dt, p, indexOfId);
}

void addSpringAccelerations(const SpringNetwork& springs, const std::vector<SpringGroup>& groups, float dt,
                            ParticleSet& p, const std::vector<uint32_t>& indexOfId) {
  tbb::parallel_for(tbb::blocked_range<size_t>(0, p.size(), 1024), [&](const tbb::blocked_range<size_t>& range) {
    for (size_t i = range.begin(); i != range.end(); ++i) {
      const SpringNetwork::End* first = springs.begin(p.id[i]);
      const SpringNetwork::End* last = springs.end(p.id[i]);
      if (first == last) continue;
      const Eigen::Vector3f xi(p.x[i], p.y[i], p.z[i]), vi(p.vx[i], p.vy[i], p.vz[i]);
      Eigen::Vector3f force = Eigen::Vector3f::Zero();
      for (const SpringNetwork::End* s = first; s != last; ++s) {
        const uint32_t q = indexOfId[size_t(s->other)];
        const Eigen::Vector3f xq(p.x[q], p.y[q], p.z[q]), vq(p.vx[q], p.vy[q], p.vz[q]);
        const Eigen::Vector3f r = xi - xq;  // r_iq
        const float length = r.norm();
        if (length <= 0.0f) continue;
        // Upwind estimate of the length change over the next step (SPEC §3.1).
        const float predicted = ((xi + vi * dt) - (xq + vq * dt)).norm();
        const float change = dt > 0.0f ? (predicted - length) / dt : 0.0f;
        const SpringGroup& g = groups[s->group];
        force += (-g.stiffness * (length - s->restLength) - g.damping * change) / length * r;  // (7)
      }
      const float invMass = 1.0f / p.mass[i];
      p.ax[i] += force.x() * invMass;
      p.ay[i] += force.y() * invMass;
      p.az[i] += force.z() * invMass;
    }
  });
}

void addMuscleAccelerations(const SpringNetwork& springs, const float* forces, ParticleSet& p,
                            const std::vector<uint32_t>& indexOfId) {
  tbb::parallel_for(tbb::blocked_range<size_t>(0, p.size(), 1024), [&](const tbb::blocked_range<size_t>& range) {
    for (size_t i = range.begin(); i != range.end(); ++i) {
      const SpringNetwork::End* first = springs.begin(p.id[i]);
      const SpringNetwork::End* last = springs.end(p.id[i]);
      Eigen::Vector3f force = Eigen::Vector3f::Zero();
      for (const SpringNetwork::End* s = first; s != last; ++s) {
        if (!s->muscles) continue;
        float f = 0.0f;
        for (uint32_t bits = s->muscles; bits; bits &= bits - 1) f += forces[std::countr_zero(bits)];
        if (f == 0.0f) continue;
        const uint32_t q = indexOfId[s->other];
        const Eigen::Vector3f r(p.x[i] - p.x[q], p.y[i] - p.y[q], p.z[i] - p.z[q]);
        const float length = r.norm();
        if (length > 0.0f) force -= (f / length) * r;
      }
      if (force.isZero(0.0f)) continue;
      const float invMass = 1.0f / p.mass[i];
      p.ax[i] += force.x() * invMass;
      p.ay[i] += force.y() * invMass;
      p.az[i] += force.z() * invMass;
    }
  });
}

float lengthRatio(const SpringNetwork& springs, const ParticleSet& p, const std::vector<uint32_t>& indexOfId,
                  size_t i) {
  double weighted = 0.0, weights = 0.0;
  for (const SpringNetwork::End* s = springs.begin(p.id[i]); s != springs.end(p.id[i]); ++s) {
    const uint32_t q = indexOfId[size_t(s->other)];
    const double length = std::sqrt(double(p.x[i] - p.x[q]) * (p.x[i] - p.x[q]) +
                                    double(p.y[i] - p.y[q]) * (p.y[i] - p.y[q]) +
                                    double(p.z[i] - p.z[q]) * (p.z[i] - p.z[q]));
    const double floored = std::max(length, double(s->restLength) / kMaxLengthRatio);
    const double w = 1.0 / s->restLength;  // (9) W_lens = 1 / r0_iq
    weighted += s->restLength / floored * w;  // (8)
    weights += w;
  }
  return weights > 0.0 ? float(weighted / weights) : 1.0f;
}

}  // namespace kurage::sim
