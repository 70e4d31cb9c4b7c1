// The telescopic body's spring-damper network (SPEC §3.1) and its stretch ratio (SPEC §3.3).
//
// Springs join every pair of a body's particles closer than the connection radius h_spr at the
// start, with rest length r0 = the initial distance. They refer to particles by their stable id
// (particle arrays are re-sorted every step), and each particle keeps the list of its own
// springs, so per-particle sums run in parallel without write conflicts and in a fixed order.
#pragma once

#include "sim/particles.h"

#include <Eigen/Core>

#include <cstdint>
#include <vector>

namespace kurage::sim {

class SpringNetwork {
public:
  struct End {
    int64_t other;     // id of the particle at the other end
    float restLength;  // r0_iq, m
  };

  // Springs between every pair closer than `radius` (metres); `ids[k]` names positions[k].
  static SpringNetwork connect(const std::vector<Eigen::Vector3f>& positions, const std::vector<int64_t>& ids,
                               float radius);

  size_t springCount() const { return ends_.size() / 2; }
  // The springs of the particle with this id (empty for an id without springs).
  const End* begin(int64_t id) const;
  const End* end(int64_t id) const;
  size_t degree(int64_t id) const { return size_t(end(id) - begin(id)); }
  int64_t minId() const { return firstId_; }
  int64_t maxId() const { return firstId_ + int64_t(offsets_.size()) - 2; }

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
// id lies in the network.
void addSpringAccelerations(const SpringNetwork& springs, float stiffness, float damping, float dt,
                            ParticleSet& particles, const std::vector<uint32_t>& indexOfId);

// (8)-(9) L_i^leng = sum_q (r0_iq / |r_iq|) W_lens / sum_q W_lens with W_lens = 1 / r0_iq, for the
// particle at sorted index i with the given id; 1 for a particle without springs.
float lengthRatio(const SpringNetwork& springs, const ParticleSet& particles, const std::vector<uint32_t>& indexOfId,
                  size_t i);

}  // namespace kurage::sim
