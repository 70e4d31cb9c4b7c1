// Weakly compressible SPH: the paper's equation of state (4), p = k_press (rho - rho0), and the
// pressure force (5) among the other forces (SPEC §1). The default solver.
#pragma once

#include "sim/solvers/pressure_solver.h"

namespace kurage::sim {

class WcsphSolver final : public PressureSolver {
public:
  explicit WcsphSolver(const FluidParams& fluid)
      : stiffness_(fluid.pressureStiffness), negative_(fluid.negativePressure),
        kernel_(fluid.kernel == SphKernel::CubicSpline ? DensityKernel::CubicSpline : DensityKernel::Poly6) {}
  std::string_view name() const override { return "wcsph"; }
  DensityKernel densityKernel() const override { return kernel_; }
  bool pressureInForces() const override { return true; }
  bool incompressible() const override { return false; }
  void afterDensity(const SolverContext& context) override;
  void correctVelocities(const SolverContext&, float) override {}
  const SolverStats& stats() const override { return stats_; }

protected:
  SolverStats& mutableStats() override { return stats_; }

private:
  float stiffness_;
  NegativePressure negative_;
  DensityKernel kernel_;  // poly6 (the paper's, with the spiky gradient) or the cubic spline
  SolverStats stats_;
};

}  // namespace kurage::sim
