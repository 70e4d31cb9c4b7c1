// Divergence-free SPH (Bender & Koschier, "Divergence-free SPH for incompressible and highly
// viscous fluids", IEEE TVCG 23(3), 2017; SCA 2015): two relaxed Jacobi solves on velocities, each
// with a per-particle factor. One unknown per particle, fluid and telescopic body alike, each with
// its own rest density rho0_i: k_i = p_i / rho_i^2 with density_sum "mass" (w_j = m_j, s_i = 1,
// c_i = rho0_i) or the pressure P_i = k_i rho0_i^2 with "volume" (w_j = V_j = m_j / rho0_j,
// s_i = rho0_i, c_i = 1). The push is the transpose of the density rate (symmetric solves; for one
// rest density the two forms are one equation), and the walls' pressure mirrors the particle's
// (k_b = k_i, hence the 2s; ours, for symmetry):
//   dv_i = -dt [sum_j w_j (k_i + k_j) grad W_ij + 2 c_i k_i gB_i]   (/ rho0_i with "volume")  (7), (10)
//   Drho_i/Dt = s_i sum_j w_j (v_i - v_j) . grad W_ij + 2 rho0_i v_i . gB_i                    (9)
//   D_i = |sum_j w_j grad W_ij + 2 c_i gB_i|^2 + m_i sum_j (w_j / s_j) |grad W_ij|^2            (13)
// gB_i = sum_b V_b grad W_ib over the walls (boundary particles, or the wall weights' tables).
// Divergence solve, after the density pass, on v: q_i += w Drho_i/Dt / D_i, applied as the push
// with q for dt k (16), until the mean |Drho/Dt| dt / rho0 is below fluid.max_divergence_error;
// two-sided for particles inside the liquid (rho_i >= 0.9 rho0_i), compressing body particles only;
// warm-started with half of each fluid particle's q of the last step. fluid.divergence_solve "cg":
// preconditioned conjugate gradients on the same operator, self-adjoint in <a, b> = sum_i
// (w_i / s_i) a_i b_i, preconditioner 1 / D_i, warm start 0.8 q.
// Constant-density solve, on v* = v + dt a_nonpressure: k_i <- max(0, k_i + w (rho*_i - rho0_i) /
// (dt^2 D_i)), rho*_i = rho_i + dt Drho_i/Dt, w = 1/2 scaled by the neighbour bound
// (solvers::relaxedNeighbours), until after two iterations at least (Alg. 3) the mean residual of
// the complementarity problem (k >= 0; |rho* - rho0| where k > 0, the compression where k = 0; over
// rho0) is below fluid.max_density_error; warm-started with each particle's k of the last step, by
// id. Before it, known pushes: the walls' hydrostatic part (Adami, Hu & Adams 2012), -dt sum_b V_b
// (g . (x_b - x_i)) grad W_ib, and under a body particle at a wall a wetting film's,
// -dt max(0, p_film - p_i) gB_i / rho0_i, p_film the hydrostatic extrapolation of the body's fluid
// neighbours' pressures. fluid.gradient_correction: L_i grad W_ij in the rate and its transpose in
// the push (Bonet & Lok 1999; walls keep the plain gradient), as M_i x_i - Y_i, nine packed floats
// a neighbour. No unknowns (SolverContext::unsolved): a held particle (its velocity is the pin's), a
// torn telescopic one (rho0_i below a quarter of its initial value; counted), and the samples of a
// body coupled as the boundary (Akinci et al. 2012): volume V_b = m_b / rho0_b growing with (10),
// the fluid's pressure mirrored onto it, its reaction m_b dv_b = -dt 2 sum_i V_b V_i P_i grad W_bi
// spread over its spring patch (linear momentum kept; the factor's own term an approximation).
// Units: k in m^5/(kg s^2) ("mass") or Pa ("volume"); the particles' pressure is what both solves
// applied, p_i = (k_i + q_i / dt_last) rho_i^2 (/ rho0_i^2 with "volume"), Pa. Kernel: the cubic
// spline, its W'(r)/r per pair from the density pass. The neighbour sums of the rate, the push and
// the factor (with the gradient correction too) are solvers/sweeps.h's: 8 particles at a time where
// the CPU runs AVX2 (the scalar sums' floats; the force pass's viscosity then sums on the same
// lists, laneLists()), else scalar; 8 or 16 neighbours at a time under
// KURAGE_SIMD=avx2|avx512 (the corrected gradient's sums scalar there). Sums reduce per chunk, then in order: the
// result does not depend on the thread count. Limits: boundary coupling needs density_sum "volume"
// and the Jacobi divergence solve; a still tank keeps some unrest at the default tolerances
// (docs/design/physics.md); a telescopic membrane solved as unknowns tears where it stretches.
#pragma once

#include "sim/solvers/pressure_solver.h"
#include "sim/solvers/solver_common.h"
#include "sim/solvers/sweeps.h"

namespace kurage::sim {

inline constexpr const char* kDfsphSummary =
    "'dfsph' (divergence-free SPH, Bender & Koschier 2017: incompressible to max_density_error, whatever the step; "
    "uses the cubic spline kernel, support_radius 2 recommended; 3 closer to Martin & Moyce in a deep slice, at "
    "about 2.5 times the cost, docs/results/validation.md)";

// How the divergence solve iterates.
enum class DivergenceSolve {
  Jacobi,             // relaxed Jacobi, as Bender & Koschier 2017 (the default)
  ConjugateGradient,  // preconditioned conjugate gradients on the same equations (ours)
};

// Scene keys (fluid.*): the tolerances in percent of rho0 and the iteration caps.
struct DfsphParams final : SolverParams {
  float maxDensityError = 0.1f;     // %: mean residual of the constant-density solve
  float maxDivergenceError = 0.1f;  // %: mean |Drho/Dt| dt / rho0 of the divergence solve
  int maxIterations = 100;
  int maxDivergenceIterations = 100;
  DivergenceSolve divergenceSolve = DivergenceSolve::Jacobi;
  std::unique_ptr<SolverParams> clone() const override { return std::make_unique<DfsphParams>(*this); }
  void describe(ParamVisitor& v) override;
  std::optional<ParamProblem> problem(const FluidParams& fluid) const override;
};

// What the solves did over the run (run.json's report; the checkpoint keeps it).
struct DfsphStats {
  uint64_t steps = 0;           // steps the solver ran
  solvers::SolveStats density;  // the constant-density solve
  solvers::SolveStats divergence;
  solvers::TornCount torn;      // torn body particles left out (SolverContext::unsolved)
};

class DfsphSolver final : public PressureSolver {
public:
  explicit DfsphSolver(const FluidParams& fluid);
  std::string_view name() const override { return "dfsph"; }
  DensityKernel densityKernel() const override { return DensityKernel::CubicSpline; }
  SphKernel ownKernel(WallDensity) const override { return SphKernel::CubicSpline; }
  bool incompressible() const override { return true; }
  StepNeeds needs() const override;
  bool couplesBoundaryBodies() const override { return true; }
  std::string boundaryCouplingProblem(const FluidParams& fluid) const override;
  void afterDensity(const SolverContext& context) override;
  void correctVelocities(const SolverContext& context, float dt) override;
  void hydrostaticHead(const std::vector<float>& headById) override;
  const DfsphStats& stats() const { return stats_; }
  SolverCounters counters() const override;
  void report(SolverReport& out) const override;
  std::vector<SolverWarning> warnings() const override;
  size_t memoryBytes() const override;
  const solvers::LaneLists* laneLists() const override { return lanes_ ? &laneLists_ : nullptr; }
  void saveState(StateWriter& out) const override;  // statistics and the warm start by id
  void restoreState(StateReader& in) override;

private:
  using Float4 = solvers::Float4;
  // velocity_ <- the particles' velocities (fourth lane 0), and back.
  void loadVelocities(const ParticleSet& p);
  void storeVelocities(ParticleSet& p) const;
  // The wall's weight in the factor and the push (header): rho0_i for density_sum "mass", 1 for
  // "volume" (whose unknowns are pressures).
  float wallWeight(const ParticleSet& p, size_t i) const { return form_ == DensitySum::Mass ? p.restDensity[i] : 1.0f; }
  // The solves' unknown per stored pi = p / rho^2: 1 for "mass", rho0_i^2 for "volume".
  float unit(const ParticleSet& p, size_t i) const {
    return form_ == DensitySum::Mass ? 1.0f : p.restDensity[i] * p.restDensity[i];
  }
  // Walls wetted by a film of the fluid under a body's particles (header): the push of the film's
  // hydrostatic pressure where it exceeds the particle's own (last step's) pressure.
  void wetWalls(const SolverContext& c, float dt);
  // Drho_i/Dt of the velocities v, per particle, into rate_.
  void densityRate(const SolverContext& c, const Float4* v);
  // v -= scale [sum_j m_j (k_i + k_j) grad W_ij + rho0_i k_i gB_i] for the per-particle k
  // (k_i L_i + k_j L_j with the gradient correction; header).
  void applyPressure(const SolverContext& c, const float* k, float scale, Float4* v);
  // The divergence solve by conjugate gradients (header), from the warm-started velocity_; adds
  // the unknowns to qSum_; returns the iterations and sets `error` (and `capped` at the cap).
  int divergenceCg(const SolverContext& c, double& error, bool& capped);
  // solvers::orderedSum with partial_.
  template <class F>
  double orderedSum(size_t count, F&& f);

  DfsphParams params_;
  float restDensity_;  // rho0 of the fluid
  CubicSplineKernel kernel_;
  DensitySum form_;
  float maxDensityError_, maxDivergenceError_;  // fractions
  int maxIterations_, maxDivergenceIterations_;
  DivergenceSolve divergenceSolve_;
  const solvers::SweepTable& sweeps_;  // the sweeps' neighbour sums (sweeps.h)
  bool scalarSums_;                    // its sums are the scalar path's: called inline
  bool lanes_ = false;                 // per step: the sums by sweeps_'s lanes
  solvers::LaneLists laneLists_;       // their interleaved lists, per step
  // During the solves (positions do not move, velocities are the unknowns' image): per particle
  // (x, y, z, w_j), w_j the density rate's weight (m_j, or m_j / rho0_j for density_sum
  // "volume"), and (vx, vy, vz, 0); written back to the particles after each solve.
  std::vector<Float4> position_, velocity_;
  std::vector<float> invFactor_;               // 1 / D_i (0 where D_i vanishes)
  std::vector<float> response_;                // per step: c_i of D_j's second term, once a particle (header)
  std::vector<float> pi_;                      // the unknown of this step (k_i, or P_i; header)
  std::vector<float> change_;                  // per iteration: the pi (or q) change
  std::vector<float> rate_;                    // Drho/Dt
  std::vector<uint8_t> active_;                // divergence solve: 1 where rho_i >= 0.9 rho0_i
  std::vector<uint8_t> fixed_;                 // no unknown of either solve: held by a pin, or a torn body particle
  std::vector<float> relax_;                   // per particle: the Jacobi relaxation
  float latticeNeighbours_ = 0.0f;             // solvers::relaxedNeighbours
  std::vector<double> partial_;                // per chunk sums
  std::vector<float> piById_;                  // warm start, by particle id
  std::vector<float> qSum_;                    // divergence solve: this step's total q
  std::vector<float> qById_;                   // its warm start, by particle id
  std::vector<double> headSum_, headCount_;    // wetWalls: per body kind
  DfsphStats stats_;
  std::vector<float> residual_, direction_, weight_;  // divergenceCg: r, d and c_i (0 off the unknowns)
  std::vector<Float4> scratch_;                       // divergenceCg: -P d
  bool corrected_ = false;                            // fluid.gradient_correction: the kernel gradient L_i grad W_ij
  std::vector<Float4> correctionRows_;                // its L_i, three rows per particle (fourth lanes 0)
  std::vector<Float4> gradientSum_;                   // per step: sum_j w_j grad W_ij (uncorrected)
  // Per push (applyPressure): w_j k_j (L00, L11, L22, L01), (w_j k_j (L02, L12), Y0, Y1) and Y2,
  // Y = w_j k_j L_j (x_j - origin_): 36 bytes a neighbour against the 48 of L_j's three rows.
  std::vector<Float4> pushTerms_;
  std::vector<Float4> reaction_;  // applyPressure: a boundary body's sample's share of its push, -m_i dv_i / M_i (header)
  std::vector<float> pushZ_;
  Float4 origin_ = {0.0f, 0.0f, 0.0f, 0.0f};          // the positions' origin in pushTerms_
  // L_i d for particle i's rows (L is symmetric: its rows are its columns).
  Float4 corrected(size_t i, Float4 d) const {
    return correctionRows_[3 * i] * d[0] + correctionRows_[3 * i + 1] * d[1] + correctionRows_[3 * i + 2] * d[2];
  }
};

}  // namespace kurage::sim
