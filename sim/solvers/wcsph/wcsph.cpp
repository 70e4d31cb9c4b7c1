#include "sim/solvers/wcsph/wcsph.h"

#include "sim/fluid.h"

#include <cmath>
#include <limits>

namespace kurage::sim {

std::optional<ParamProblem> WcsphParams::problem(const FluidParams& fluid) const {
  if (fluid.gradientCorrection && fluid.pressureForce == PressureForce::Mueller2003)
    return ParamProblem{"fluid.gradient_correction",
                        "corrects Monaghan's pressure force (fluid.pressure_force \"monaghan1992\") or dfsph's solves; "
                        "the paper's force \"mueller2003\" has no corrected form"};
  return std::nullopt;
}

WcsphSolver::WcsphSolver(const FluidParams& fluid)
    : stiffness_(fluid.pressureStiffness), spacing_(fluid.spacing), negative_(fluid.negativePressure),
      force_(fluid.pressureForce),
      kernel_(fluid.kernel == SphKernel::CubicSpline ? DensityKernel::CubicSpline : DensityKernel::Poly6) {}

SphKernel WcsphSolver::ownKernel(WallDensity walls) const {
  // The paper's pair let a still tank between boundary particles gain energy (docs/design/physics.md)
  return walls == WallDensity::BoundaryParticles ? SphKernel::CubicSpline : SphKernel::Mueller2003;
}

StepNeeds WcsphSolver::needs() const {
  StepNeeds n;
  n.pressureForce = true;
  n.wallPenaltyStiffness = stiffness_ / (spacing_ * spacing_);  // k = c^2 / l^2
  n.wallPenaltyRest = 0.5f * spacing_;
  return n;
}

void WcsphSolver::afterDensity(const SolverContext& context) {
  computePressure(context.particles, stiffness_, negative_);  // (4)
  ++steps_;
}

void WcsphSolver::hydrostaticLattice(std::vector<std::vector<Eigen::Vector3f>>& blocks, const std::vector<float>& tops,
                                     float g) const {
  // The lattice compressed vertically to the density whose pressure carries the column,
  // rho(d) = rho0 (1 + f g d / k) with f = 1 (Monaghan's force) or 2 ((5) recovers half of grad p).
  // A layer at height z above the block's floor z_b moves to
  // z_b + int_{z_b}^{z} rho0 / rho(d(z')) dz' = z_b + (k / (f g)) ln((1 + a d_b) / (1 + a d)),
  // a = f g / k, d = top - z (the uncompressed depth: the error is second order in a d).
  const float f = force_ == PressureForce::Mueller2003 ? 2.0f : 1.0f;
  const float a = f * g / stiffness_;
  for (size_t b = 0; b < blocks.size(); ++b) {
    float bottom = std::numeric_limits<float>::infinity();
    for (const Eigen::Vector3f& q : blocks[b]) bottom = std::min(bottom, q.z());
    const float db = tops[b] - bottom;
    for (Eigen::Vector3f& q : blocks[b]) q.z() = bottom + std::log((1.0f + a * db) / (1.0f + a * (tops[b] - q.z()))) / a;
  }
}

}  // namespace kurage::sim
