// Emitters and sinks: sources and outflows of fluid particles.
#pragma once

#include "sim/params.h"
#include "sim/particles.h"
#include "sim/state.h"

#include <cstdint>
#include <vector>

namespace kurage::sim {

// Offsets of `count` points spread uniformly over a disc of radius `radius` (Vogel's sunflower
// pattern: point k at radius R sqrt((k + 1/2) / count), angle k times the golden angle), in the
// plane spanned by the unit vectors u and v.
std::vector<Eigen::Vector3f> discPattern(int count, float radius, const Eigen::Vector3f& u, const Eigen::Vector3f& v);

class Emitter {
public:
  Emitter(const EmitterParams& params, float spacing);

  // Called after a step from t - dt to t: spawns the layers that left the nozzle during the step
  // (particles of the given mass and rest density, kind 0, ids from nextId), skipping positions
  // closer than half a spacing to an existing particle; in the step the nozzle closes, a last
  // layer more than half out goes too. Returns the number spawned.
  size_t emit(double t, float dt, ParticleSet& particles, float mass, float restDensity, int64_t& nextId);

  // Particles this emitter will spawn over its whole life, for reserving storage.
  size_t expectedTotal() const;
  size_t blocked() const { return blocked_; }
  size_t spawned() const { return emitted_ - blocked_; }  // particles it has added
  // What it carries from step to step, for checkpoints.
  void saveState(StateWriter& out) const;
  void restoreState(StateReader& in);

private:
  EmitterParams params_;
  float spacing_;
  Eigen::Vector3f direction_, u_, v_;
  double travelled_ = 0.0;    // distance the fluid moved out of the nozzle since the last layer
  double emittedTarget_ = 0.0;  // particles owed so far (fractional)
  size_t emitted_ = 0;
  size_t blocked_ = 0;
};

// Removes the fluid particles (kind 0) inside the sink's box; returns how many. `flags` is
// scratch storage of the caller.
size_t applySink(const SinkParams& sink, ParticleSet& particles, std::vector<uint8_t>& flags);

}  // namespace kurage::sim
