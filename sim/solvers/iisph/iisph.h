// Implicit incompressible SPH (Ihmsen, Cornelis, Solenthaler, Horvath & Teschner, "Implicit
// incompressible SPH", IEEE TVCG 20(3), 2014): after the non-pressure forces, the pressure that
// brings every particle's predicted density to its rest density, from the discretised pressure
// Poisson equation solved by relaxed Jacobi (the paper's Sect. 3 and Algorithm 1), matrix-free.
//
// Per particle an unknown k_i (k = p / rho^2 with density_sum "mass", the pressure P ~ p rho0^2 /
// rho^2 in Pa with "volume"; each particle with its own rest density rho0_i, so body particles are
// unknowns beside the fluid's). The pressure's acceleration, momentum-conserving, walls mirrored:
//   (I1) a_i = -[sum_j w_j (k_i + k_j) grad W_ij + 2 c_i k_i gB_i]   (/ rho0_i for "volume")
// with w_j = m_j, c_i = rho0_i ("mass") or w_j = V_j = m_j / rho0_j, c_i = 1 ("volume"), and
// gB_i = sum_b V_b grad W_ib over the walls (boundary particles, or the wall weights' tables).
// The density a velocity field v gives after the step, as the continuity equation's rate:
//   (I2) Drho_i/Dt = s_i sum_j w_j (v_i - v_j) . grad W_ij + 2 rho0_i v_i . gB_i
// (s_i = 1 or rho0_i). The predicted density of v* = v + dt a_nonpressure plus the pressure's
//   (I3) rho*_i = rho_i + dt Drho_i/Dt(v*) + dt^2 Drho_i/Dt(a(k))
// is linear in k; its diagonal, the paper's a_ii, is -dt^2 D_i with
//   (I4) D_i = |sum_j w_j grad W_ij + 2 c_i gB_i|^2 + m_i sum_j (w_j / s_j) |grad W_ij|^2.
// Each iteration computes (I1) and (I3) for all particles and sets
//   (I5) k_i <- max(0, k_i + w_i (rho*_i - rho0_i) / (dt^2 D_i))
// (relaxed Jacobi, the paper's omega = fluid.relaxation, 0.5; w_i = omega min(1, n / n_i),
// solvers::relaxedNeighbours: a body at half the fluid spacing has 8 times the neighbours and
// diverges at the fluid's omega), until, after at least two, the mean residual over particles of
// the complementarity problem (k >= 0; |rho* - rho0| / rho0 where k > 0, the compression where
// k = 0) is below fluid.max_density_error (%), at most fluid.max_iterations; then
// v = v* + dt a(k). It starts from fluid.warm_start times each particle's k of the previous step
// (the paper's 1/2; kept by particle id), or from the hydrostatic start's rho0 g depth.
//
// Ours: the wall's term counts twice (mirrored pressure, k_b = k_i) in (I1) and (I2), so the
// system is symmetric, as DFSPH's (sim/solvers/dfsph/dfsph.h); the walls' hydrostatic part
// (Adami, Hu & Adams 2012), -dt sum_b V_b (g . (x_b - x_i)) grad W_ib, is applied to v* first.
// Particles a pin holds, and torn telescopic ones (SolverContext::unsolved), are no unknowns
// (k = 0, no error); the held ones keep their velocity.
//
// Units: k in m^5/(kg s^2) ("mass") or Pa ("volume"); the particles' `pressure` is
// p_i = k_i rho_i^2 (/ rho0_i^2 for "volume"), Pa. Limits: no divergence solve (a still tank is
// as calm as its tolerance); no bodies coupled as the boundary (bodies[].coupling "solved"
// only); no gradient correction; the cubic spline kernel. Sums reduce in a fixed order: the
// result does not depend on the number of threads.
#pragma once

#include "sim/solvers/pressure_solver.h"
#include "sim/solvers/solver_common.h"
#include "sim/solvers/sweeps.h"

namespace kurage::sim {

inline constexpr const char* kIisphSummary =
    "'iisph' (implicit incompressible SPH, Ihmsen et al. 2014: the pressure Poisson equation by relaxed Jacobi, "
    "incompressible to max_density_error; no divergence solve; the cubic spline kernel)";

// Scene keys (fluid.*).
struct IisphParams final : SolverParams {
  float maxDensityError = 0.1f;  // %: mean residual of the solve
  int maxIterations = 100;
  float relaxation = 0.5f;       // omega
  float warmStart = 0.5f;        // of the previous step's pressure
  std::unique_ptr<SolverParams> clone() const override { return std::make_unique<IisphParams>(*this); }
  void describe(ParamVisitor& v) override;
  std::optional<ParamProblem> problem(const FluidParams& fluid) const override;
};

// What the solve did over the run (run.json's report; the checkpoint keeps it).
struct IisphStats {
  uint64_t steps = 0;
  solvers::SolveStats density;
  solvers::TornCount torn;
};

class IisphSolver final : public PressureSolver {
public:
  explicit IisphSolver(const FluidParams& fluid);
  std::string_view name() const override { return "iisph"; }
  DensityKernel densityKernel() const override { return DensityKernel::CubicSpline; }
  SphKernel ownKernel(WallDensity) const override { return SphKernel::CubicSpline; }
  bool incompressible() const override { return true; }
  StepNeeds needs() const override;
  void afterDensity(const SolverContext& context) override;
  void correctVelocities(const SolverContext& context, float dt) override;
  void hydrostaticHead(const std::vector<float>& headById) override;
  const IisphStats& stats() const { return stats_; }
  SolverCounters counters() const override;
  void report(SolverReport& out) const override;
  std::vector<SolverWarning> warnings() const override;
  size_t memoryBytes() const override;
  void saveState(StateWriter& out) const override;  // statistics and the warm start by id
  void restoreState(StateReader& in) override;

private:
  using Float4 = solvers::Float4;
  // (I1) for the unknowns k, into acceleration_.
  void accelerate(const SolverContext& c, const float* k);
  // (I2) of the velocities v, into rate_.
  void densityRate(const SolverContext& c, const Float4* v);
  // The unknown per stored p / rho^2: 1 for "mass", rho0_i^2 for "volume".
  float unit(const ParticleSet& p, size_t i) const {
    return form_ == DensitySum::Mass ? 1.0f : p.restDensity[i] * p.restDensity[i];
  }
  float wallWeight(const ParticleSet& p, size_t i) const { return form_ == DensitySum::Mass ? p.restDensity[i] : 1.0f; }

  IisphParams params_;
  float restDensity_;
  DensitySum form_;
  CubicSplineKernel kernel_;
  float neighbourBound_;            // solvers::relaxedNeighbours
  const solvers::SweepTable& sweeps_;  // the sweeps' neighbour sums (sweeps.h)
  std::vector<Float4> position_;    // (x, y, z, w_j)
  std::vector<Float4> velocity_;    // v* during the solve
  std::vector<Float4> acceleration_;  // (I1)
  std::vector<float> invFactor_;    // 1 / D_i, 0 for no unknown
  std::vector<float> relax_;        // w_i
  std::vector<uint8_t> held_;       // a pin holds it: its velocity is the pin's
  std::vector<float> source_;       // rho_i + dt Drho_i/Dt(v*) - rho0_i
  std::vector<float> rate_;
  std::vector<float> k_, next_;
  std::vector<double> partial_;
  std::vector<float> warmById_;     // the next step's starting k (as p / rho^2), by particle id
  IisphStats stats_;
};

}  // namespace kurage::sim
