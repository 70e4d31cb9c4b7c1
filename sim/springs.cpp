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
  std::vector<Eigen::Vector3f> scratch;
  addSpringAccelerations(springs, std::vector<SpringGroup>{{stiffness, damping, false}}, dt, p, indexOfId, scratch);
}

void addSpringAccelerations(const SpringNetwork& springs, const std::vector<SpringGroup>& groups, float dt,
                            ParticleSet& p, const std::vector<uint32_t>& indexOfId,
                            std::vector<Eigen::Vector3f>& predicted) {
  if (springs.springCount() == 0) return;
  const int64_t firstId = springs.minId(), lastId = springs.maxId();
  bool anyImplicit = false;
  for (const SpringGroup& g : groups) anyImplicit = anyImplicit || (g.implicitDamper && g.damping > 0.0f);
  // Springs, and the dampers integrated explicitly: each particle sums its own springs in parallel.
  tbb::parallel_for(tbb::blocked_range<int64_t>(firstId, lastId + 1, 256), [&](const tbb::blocked_range<int64_t>& range) {
    for (int64_t id = range.begin(); id != range.end(); ++id) {
      const SpringNetwork::End* first = springs.begin(id);
      const SpringNetwork::End* last = springs.end(id);
      if (first == last) continue;
      const size_t i = indexOfId[size_t(id)];
      const Eigen::Vector3f xi(p.x[i], p.y[i], p.z[i]), vi(p.vx[i], p.vy[i], p.vz[i]);
      Eigen::Vector3f force = Eigen::Vector3f::Zero();
      for (const SpringNetwork::End* s = first; s != last; ++s) {
        const uint32_t q = indexOfId[s->other];
        const Eigen::Vector3f xq(p.x[q], p.y[q], p.z[q]);
        const Eigen::Vector3f r = xi - xq;  // r_iq
        const float length = r.norm();
        if (length <= 0.0f) continue;
        const SpringGroup& g = groups[s->group];
        float magnitude = -g.stiffness * (length - s->restLength);  // (7), spring
        if (!g.implicitDamper) {
          // (7), damper: upwind estimate of the length change over the next step (SPEC §3.1).
          const Eigen::Vector3f vq(p.vx[q], p.vy[q], p.vz[q]);
          const float predictedLength = ((xi + vi * dt) - (xq + vq * dt)).norm();
          magnitude -= g.damping * (dt > 0.0f ? (predictedLength - length) / dt : 0.0f);
        }
        force += magnitude / length * r;
      }
      const float invMass = 1.0f / p.mass[i];
      p.ax[i] += force.x() * invMass;
      p.ay[i] += force.y() * invMass;
      p.az[i] += force.z() * invMass;
    }
  });
  if (!anyImplicit || !(dt > 0.0f)) return;
  // Implicit dampers: from the velocities after every other force, v* = v + a dt, each spring in
  // turn (a fixed order) lets its ends' relative velocity along it, w = r^.(v_i - v_q), decay
  // exactly as its damper alone would over dt: w' = w exp(-d (1/m_i + 1/m_q) dt), momentum kept.
  // Each update only removes relative motion, so no step size makes it unstable.
  predicted.resize(size_t(lastId - firstId + 1));
  for (int64_t id = firstId; id <= lastId; ++id) {
    const size_t i = indexOfId[size_t(id)];
    if (i != UINT32_MAX)
      predicted[size_t(id - firstId)] = Eigen::Vector3f(p.vx[i] + p.ax[i] * dt, p.vy[i] + p.ay[i] * dt, p.vz[i] + p.az[i] * dt);
  }
  // One spring's damper over half the step (the sweep runs forward, then backward).
  auto damp = [&](int64_t id, size_t i, const SpringNetwork::End& s) {
    if (int64_t(s.other) <= id) return;  // each spring once, from its lower id
    const SpringGroup& g = groups[s.group];
    if (!g.implicitDamper || g.damping <= 0.0f) return;
    const uint32_t q = indexOfId[s.other];
    Eigen::Vector3f r(p.x[i] - p.x[q], p.y[i] - p.y[q], p.z[i] - p.z[q]);
    const float length = r.norm();
    if (length <= 0.0f) return;
    r /= length;
    Eigen::Vector3f& vi = predicted[size_t(id - firstId)];
    Eigen::Vector3f& vq = predicted[size_t(int64_t(s.other) - firstId)];
    const float wi = 1.0f / p.mass[i], wq = 1.0f / p.mass[q];
    const float w = r.dot(vi - vq);
    const float change = w * (std::exp(-0.5f * g.damping * (wi + wq) * dt) - 1.0f);  // w' - w
    vi += (change * wi / (wi + wq)) * r;
    vq -= (change * wq / (wi + wq)) * r;
  };
  // A forward then a backward sweep: the composed update is symmetric (self-adjoint in the mass
  // inner product), so, unlike a single sweep, it never turns relative motion against the forces.
  for (int64_t id = firstId; id <= lastId; ++id)
    for (const SpringNetwork::End* s = springs.begin(id); s != springs.end(id); ++s) damp(id, indexOfId[size_t(id)], *s);
  for (int64_t id = lastId; id >= firstId; --id)
    for (const SpringNetwork::End* s = springs.end(id); s != springs.begin(id);) {
      --s;
      damp(id, indexOfId[size_t(id)], *s);
    }
  for (int64_t id = firstId; id <= lastId; ++id) {
    const size_t i = indexOfId[size_t(id)];
    if (i == UINT32_MAX) continue;
    const Eigen::Vector3f& v = predicted[size_t(id - firstId)];
    p.ax[i] = (v.x() - p.vx[i]) / dt;
    p.ay[i] = (v.y() - p.vy[i]) / dt;
    p.az[i] = (v.z() - p.vz[i]) / dt;
  }
}

void addMuscleAccelerations(const SpringNetwork& springs, const float* forces, const float* const* weights, ParticleSet& p,
                            const std::vector<uint32_t>& indexOfId) {
  if (springs.springCount() == 0) return;
  tbb::parallel_for(tbb::blocked_range<int64_t>(springs.minId(), springs.maxId() + 1, 256),
                    [&](const tbb::blocked_range<int64_t>& range) {
    for (int64_t id = range.begin(); id != range.end(); ++id) {
      const SpringNetwork::End* first = springs.begin(id);
      const SpringNetwork::End* last = springs.end(id);
      if (first == last) continue;
      const size_t i = indexOfId[size_t(id)];
      Eigen::Vector3f force = Eigen::Vector3f::Zero();
      for (const SpringNetwork::End* s = first; s != last; ++s) {
        if (!s->muscles) continue;
        float f = 0.0f;
        for (uint32_t bits = s->muscles; bits; bits &= bits - 1) {
          const int m = std::countr_zero(bits);
          const float* w = weights ? weights[m] : nullptr;
          f += w ? forces[m] * 0.5f * (w[id] + w[s->other]) : forces[m];
        }
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
