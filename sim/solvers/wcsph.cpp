#include "sim/solvers/wcsph.h"

#include "sim/fluid.h"

namespace kurage::sim {

void WcsphSolver::afterDensity(const SolverContext& context) {
  computePressure(context.particles, stiffness_, negative_);  // (4)
  ++stats_.steps;
}

}  // namespace kurage::sim
