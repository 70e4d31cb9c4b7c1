#include "sim/boundary.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace kurage::sim {

void enforceBoxWalls(ParticleSet& particles, const ContainerParams& container) {
  float* pos[3] = {particles.x.data(), particles.y.data(), particles.z.data()};
  float* vel[3] = {particles.vx.data(), particles.vy.data(), particles.vz.data()};
  const bool noSlip = container.walls == WallSlip::NoSlip;
  tbb::parallel_for(tbb::blocked_range<size_t>(0, particles.size(), 4096), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) {
      bool hit = false;
      for (int a = 0; a < 3; ++a) {
        float& p = pos[a][i];
        if (p < container.min[a]) {
          p = container.min[a];  // back onto the wall, zero distance
          if (vel[a][i] < 0.0f) vel[a][i] = 0.0f;
          hit = true;
        } else if (p > container.max[a]) {
          p = container.max[a];
          if (vel[a][i] > 0.0f) vel[a][i] = 0.0f;
          hit = true;
        }
      }
      if (hit && noSlip) vel[0][i] = vel[1][i] = vel[2][i] = 0.0f;  // the paper's no-slip
    }
  });
}

}  // namespace kurage::sim
