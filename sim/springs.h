// The telescopic body's spring-damper network (SPEC §3.1) and its stretch ratio (SPEC §3.3).
//
// Springs join every pair of a body's particles closer than the connection radius h_spr at the
// start, with rest length r0 = the initial distance. They refer to particles by their stable id
// (particle arrays are re-sorted every step), and each particle keeps the list of its own
// springs, so per-particle sums run in parallel without write conflicts and in a fixed order.
#pragma once

#include "sim/params.h"
#include "sim/particles.h"

#include <Eigen/Core>

#include <algorithm>
#include <cstdint>
#include <vector>

namespace kurage::sim {

// The coefficients of a set of springs (one per body): k (N/m) and d (N s/m) of (7), and how
// the damper is integrated (BodyParams::damper).
struct SpringGroup {
  float stiffness = 0.0f;
  float damping = 0.0f;
  bool implicitDamper = false;
};

// One spring as given to the builder: the ids of its ends, rest length, coefficient group and the
// muscles it belongs to (bit m set: muscle m pulls on it).
struct SpringPair {
  int64_t a = 0, b = 0;
  float restLength = 0.0f;
  uint16_t group = 0;
  uint32_t muscles = 0;
};

// The pairs closer than `radius` (and not coincident) among `positions`, named by `ids`.
std::vector<SpringPair> springPairsWithin(const std::vector<Eigen::Vector3f>& positions,
                                          const std::vector<int64_t>& ids, float radius, uint16_t group = 0);

class SpringNetwork {
public:
  static constexpr int kMaxMuscles = 32;
  struct End {
    uint32_t other;     // id of the particle at the other end
    float restLength;   // r0_iq, m
    uint16_t group;     // index of the spring's SpringGroup
    uint32_t muscles;   // bit m: muscle m acts on this spring
  };

  // Springs between every pair closer than `radius` (metres); `ids[k]` names positions[k].
  static SpringNetwork connect(const std::vector<Eigen::Vector3f>& positions, const std::vector<int64_t>& ids,
                               float radius);
  // The network of the given springs; ids must lie in [0, 2^32).
  static SpringNetwork fromPairs(const std::vector<SpringPair>& pairs);

  size_t springCount() const { return ends_.size() / 2; }
  // The springs of the particle with this id (empty for an id without springs).
  const End* begin(int64_t id) const;
  const End* end(int64_t id) const;
  size_t degree(int64_t id) const { return size_t(end(id) - begin(id)); }
  bool connected(int64_t a, int64_t b) const;
  int64_t minId() const { return firstId_; }
  int64_t maxId() const { return firstId_ + int64_t(offsets_.size()) - 2; }
  size_t memoryBytes() const { return offsets_.capacity() * sizeof(uint32_t) + ends_.capacity() * sizeof(End); }

private:
  int64_t firstId_ = 0;
  std::vector<uint32_t> offsets_;  // by id - firstId_, size ids + 1
  std::vector<End> ends_;
};

// index[id] = position of that particle in the (sorted) arrays; call after every re-sort.
void indexParticlesById(const ParticleSet& particles, std::vector<uint32_t>& index);

// (7) F_i = sum_q [ -k (|r_iq| - r0_iq) - d dl_iq / dt ] r_iq / |r_iq|,  r_iq = r_i - r_q,
// with the upwind length change dl_iq = |(r_i + v_i dt) - (r_q + v_q dt)| - |r_iq|: the damper
// opposes the change of length. Adds F_i / m_i to the accelerations of the particles whose
// id lies in the network. For a group with an implicit damper the damper is not in F_i: after
// every other acceleration (call this last), each spring in a fixed order lets its ends' relative
// velocity along it decay exactly as its damper alone would over dt (w' = w exp(-d (1/m_i +
// 1/m_q) dt), momentum kept), so the damper never bounds the step; `scratch` is reused storage.
void addSpringAccelerations(const SpringNetwork& springs, const std::vector<SpringGroup>& groups, float dt,
                            ParticleSet& particles, const std::vector<uint32_t>& indexOfId,
                            std::vector<Eigen::Vector3f>& scratch);
// The same with one group of coefficients for every spring.
void addSpringAccelerations(const SpringNetwork& springs, float stiffness, float damping, float dt,
                            ParticleSet& particles, const std::vector<uint32_t>& indexOfId);

// Muscles (SPEC §4.2, §4.3): muscle m pulls the ends of each of its springs together with force
// forces[m] (N; negative pushes them apart): F_i += -sum_q sum_m f_m w_m r_iq / |r_iq|, where
// w_m = (weights[m][i] + weights[m][q]) / 2 for a muscle with per-particle weights (indexed by id;
// a righting muscle) and 1 where weights is null or weights[m] is null.
void addMuscleAccelerations(const SpringNetwork& springs, const float* forces, const float* const* weights,
                            ParticleSet& particles,
                            const std::vector<uint32_t>& indexOfId);

// (8)-(9) L_i^leng = sum_q (r0_iq / |r_iq|) W_lens / sum_q W_lens with W_lens = 1 / r0_iq, for the
// particle at sorted index i with the given id; 1 for a particle without springs. Each spring's
// |r_iq| is floored at r0_iq / kMaxLengthRatio so that a collapsed spring gives a finite ratio.
constexpr float kMaxLengthRatio = 10.0f;
float lengthRatio(const SpringNetwork& springs, const ParticleSet& particles, const std::vector<uint32_t>& indexOfId,
                  size_t i);

// The L^leng that (10) uses under a measure: (8) itself, or (ours) min(1, (8)), so that only a
// stretch lowers the rest density.
inline float telescopicLengthRatio(TelescopicMeasure measure, float leng) {
  return measure == TelescopicMeasure::StretchOnly ? std::min(leng, 1.0f) : leng;
}

}  // namespace kurage::sim
