// Weakly compressible SPH, the paper's solver and the default: the equation of state (4),
// p = k_press (rho - rho0) (clamped at 0 unless fluid.negative_pressure "keep"), and the pressure
// force (5) among the other forces (SPEC §1). Its parameters are the fluid's (k_press,
// fluid.pressure_force, fluid.negative_pressure: SPEC §2), so it declares none of its own.
// Walls of boundary particles push with a penalty as stiff as the fluid, k = c^2 / l^2, holding
// the first layer at its lattice place half a spacing in (fluid.h WallSums; docs/design/physics.md
// "Walls under WCSPH"). Its hydrostatic start compresses each column to the density whose
// pressure carries it (hydrostaticLattice).
#pragma once

#include "sim/solvers/pressure_solver.h"

namespace kurage::sim {

inline constexpr const char* kWcsphSummary =
    "'wcsph' (the paper: p = k_press (rho - rho0), a weakly compressible fluid whose compression depends on "
    "k_press)";

struct WcsphParams final : SolverParams {
  std::unique_ptr<SolverParams> clone() const override { return std::make_unique<WcsphParams>(*this); }
  void describe(ParamVisitor&) override {}
  std::optional<ParamProblem> problem(const FluidParams& fluid) const override;
};

class WcsphSolver final : public PressureSolver {
public:
  explicit WcsphSolver(const FluidParams& fluid);
  std::string_view name() const override { return "wcsph"; }
  DensityKernel densityKernel() const override { return kernel_; }
  SphKernel ownKernel(WallDensity walls) const override;
  bool incompressible() const override { return false; }
  StepNeeds needs() const override;
  void afterDensity(const SolverContext& context) override;
  void hydrostaticLattice(std::vector<std::vector<Eigen::Vector3f>>& blocks, const std::vector<float>& tops,
                          float g) const override;
  SolverCounters counters() const override { return {steps_, {}}; }
  void saveState(StateWriter& out) const override { out.value(steps_); }
  void restoreState(StateReader& in) override { steps_ = in.value<uint64_t>(); }

private:
  float stiffness_, spacing_;
  NegativePressure negative_;
  PressureForce force_;
  DensityKernel kernel_;  // poly6 (the paper's, with the spiky gradient) or the cubic spline
  uint64_t steps_ = 0;
};

}  // namespace kurage::sim
