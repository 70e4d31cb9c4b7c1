// Divergence-free SPH (Bender & Koschier, "Divergence-free smoothed particle hydrodynamics",
// SCA 2015, and "Divergence-free SPH for incompressible and highly viscous fluids", IEEE TVCG
// 23(3), 2017): two Jacobi-style solvers on velocities, each with a per-particle factor.
//
// Notation (ours, one set of equations for fluid and telescopic-body particles alike, each with
// its own rest density rho0_i, so (8)-(10) still act). With density_sum "mass" (rho_i =
// sum_j m_j W_ij) the unknown is k_i = p_i / rho_i^2 and the pressure changes velocities by
//   dv_i = -dt [ sum_j m_j (k_i + k_j) grad W_ij + 2 rho0_i k_i gB_i ]           (2017, eq. 7, 10)
// With "volume" (rho_i = rho0_i sum_j V_j W_ij, V_j = m_j / rho0_j) the unknown is the pressure
// P_i = k_i rho0_i^2 and the push is the transpose of that density's rate (the gradient of its
// potential energy, so the system the solves iterate on is symmetric when rest densities differ):
//   dv_i = -(dt / rho0_i) [ sum_j V_j (P_i + P_j) grad W_ij + 2 P_i gB_i ]
// For one rest density the two are the same equation. gB_i = sum_b V_b grad W_ib over the wall's
// boundary particles (or its lateral average from the wall weights' tables), which carry the particle's own pressure (Akinci 2012, mirrored: k_b = k_i,
// hence the 2). With a factor 1 instead, the symmetric sum leaves a particle on a flat wall with
// no push of its own away from it: the fluid-only part of sum_j m_j k_i grad W_ij cancels the
// wall's term, and the neighbours above press it into the wall (measured: the floor layer sank
// into the wall within five steps).
// (The mass form's push with the volume form's density rate, used before, is not symmetric
// between a body particle and the fluid: a box resting on the floor of box.json made the
// constant-density solve diverge, its pressure growing 2.5-fold an iteration, and the run stopped
// with a non-finite velocity after about 17 s; docs/PHYSICS.md.)
// The density's rate of change, with w_j = m_j and s_i = 1 ("mass") or w_j = V_j, s_i = rho0_i
// ("volume"):
//   Drho_i/Dt = s_i [ sum_j w_j (v_i - v_j) . grad W_ij ] + 2 rho0_i v_i . gB_i    (2017, eq. 9)
// The wall's term is counted twice here too (ours): the exact rate has 1, but then the system
// the Jacobi iteration solves is not symmetric at walls and its pressure grew without bound in
// a checkerboard along the tank's edges (measured); with 2 it is symmetric, and at rest, where
// the velocities vanish, the result is the same.
// The unknown alone (Jacobi) changes it by -dt^2 k_i D_i with the factor (2017, eq. 13)
//   D_i = |F_i|^2 + m_i sum_j c_j |grad W_ij|^2,  F_i = sum_j w_j grad W_ij + 2 c gB_i,
// c_j = w_j, c = rho0_i ("mass"), or c_j = V_j / rho0_j, c = 1 ("volume").
//
// With fluid.gradient_correction (ours; Bonet & Lok 1999's L_i, computeGradientCorrection in
// fluid.h, handed over in the context) the rate uses the corrected gradient L_i grad W_ij and the
// push is its transpose, so the solves stay symmetric:
//   Drho_i/Dt = s_i sum_j w_j (v_i - v_j) . L_i grad W_ij + (the wall's term)
//   dv_i = -dt [ sum_j w_j (k_i L_i + k_j L_j) grad W_ij + (the wall's term) ]  (/ rho0_i for "volume")
//   D_i = |L_i sum_j w_j grad W_ij + 2 c gB_i|^2 + m_i sum_j c_j |L_i grad W_ij|^2.
// The walls' terms keep the plain gradient (L_i = I within h of a wall). (WCSPH's force pairs
// the two as (L_i + L_j) / 2, which is not the transpose of a corrected rate.) The push's
// neighbour sum is formed as M_i x_i - Y_i, M_i = sum_j s_ij w_j k_j L_j, Y_i = sum_j s_ij w_j k_j
// L_j x_j (s_ij = W'(r)/r), from nine floats a particle written once a push: 36 bytes a
// neighbour instead of L_j's rows and x_j (measured: 75-77 -> 65-66 ms a step on bench sim's
// dam break, 100,800 particles, 2 threads).
//
// Particles that are no unknowns (ours; SolverContext::unsolved, BodySystem::markUnsolved): neither
// solve gives them a pressure or counts their error.
// - A particle a pin holds: its velocity is the pin's, so no push moves it. Before, the solves
//   pushed it, the pin undid the push, and the warm-started pressure of a rim particle compressed
//   by its pinned neighbours grew step after step (8 MPa under 5 m of water) until it tore the
//   loaded membrane of membrane.json apart (non-finite at t = 8.2 s).
// - A telescopic body particle whose rest density (10) has fallen below a quarter of its initial
//   one (BodySystem::kTornDensityRatio; "torn", stretched past what the solves can hold; counted
//   in DfsphStats::tornSteps, and `kurage sim` warns). With its volume m/rho0 grown that much,
//   its own kernel's share of its density, m_i W(0), approaches its rest density and it has few
//   neighbours (D_i small), so no pressure brings it to rest density: its pressure grew without
//   bound and flung it out at hundreds of m/s (the same membrane, once its rim was held, at
//   t = 6.9 s; rho0_i fell from 112 to 82 kg/m^3, m_i W(0) = 104, in 0.05 s). It still feels its
//   neighbours' pressure.
//
// Bodies as the fluid's boundary (ours; BodyParams::coupling "boundary", docs/PHYSICS.md). Such a
// body's particles are no unknowns of either solve (kBoundary; SolverContext::boundaryBodies). The
// fluid meets them as boundary samples (Akinci et al. 2012) of volume V_b = m_b / rho0_b, which
// (10) grows as (L^leng)^-3 as the body stretches: the paper's "a stretched body pushes the fluid
// away harder", in the form an incompressible fluid feels, its density sum. A fluid particle's
// pressure is mirrored onto the sample (P_b = P_i), so a fluid-sample pair counts twice in the
// factor, the density rate and the push, as the walls' samples do (the sample's weight w_b is
// stored doubled). For the density rate this is a choice made for symmetry, as at the walls:
// exact for a sample at rest, it counts a moving sample's approach twice. The sample's own
// response in D_i is taken undoubled and unspread, an approximation. Samples have no pressure, so
// the walls' mirrored push, their hydrostatic part and the wetted film leave them alone: the
// fluid pushes them, the wall clamp keeps them in. The sample takes the push's reaction,
//   m_b dv_b = -dt 2 sum_i V_b V_i P_i grad W_bi                (equal and opposite to its fluid
// neighbours' share), but not alone: the reaction is spread over its patch, itself and its spring
// neighbours (BodySystem::boundaryPatches), each particle q of it gaining m_b dv_b / M_b, M_b the
// patch's mass. The patch takes the impulse the sample would have (linear momentum is kept, not
// angular momentum about the patch; a pin takes its particle's share). A membrane carries a load on its area through its neighbours; its
// springs (the paper's k = 30 N/m) are far too soft to pass it on within a step, and a stretched
// sample, pushed in proportion to its grown volume with the mass it had, was thrown at hundreds
// of m/s (docs/investigations/pressure_solvers.md): with the reactions on the samples alone, seven
// of eight runs of membrane_dfsph.json stopped (their step under time_step.min_step) and its
// conventional twin let all 85 poured particles through; with the spreading 0 and 54-61.
//
// Walls wetted by the fluid (ours): a body resting on a wall has no fluid under it, so the mirrored
// wall alone gives it no buoyancy there, and box.json's box, released on the floor, stayed on it
// (a real box lifts as water seeps under it; a 1 m particle cannot). Under a body particle the
// wall's pressure is therefore at least that of a film of the fluid at rest at its height: the
// hydrostatic extrapolation p_film(x) = mean_j (p_j + rho0 g . (x - x_j)) over the body's fluid
// neighbours j (last step's pressures), applied as the known push
//   dv_i = -dt max(0, p_film(x_i) - p_i) gB_i / rho0_i
// before the constant-density solve. Fluid particles and bodies away from walls are unaffected.
//
// Divergence solve (after the density pass, on the current velocities): q_i = w Drho_i/Dt / D_i
// and v_i changes by the push above with q for dt k (dt P), until the mean of
// |Drho/Dt| dt / rho0 is below fluid.max_divergence_error (%), at most
// max_divergence_iterations. It is warm-started with half of each fluid particle's total q of
// the previous step (kept by id), as SPlisHSPlasH does (measured on bench sim's dam break: 8.2
// divergence iterations a step without, 4.9 with); body particles start from 0 (warm-started
// too, they held the contracted box of box.json 1.5 spacings above the floor). The conjugate-
// gradient solve below starts from 0.8 of the previous q instead (ours): converged tighter, its q
// carries over better (bench sim's dam break at max_divergence_error 0.01 % with the gradient
// correction: 8.6 -> 5.5 divergence iterations a step; Jacobi at 0.8: 2.1 -> 2.3). Particles with
// rho_i < 0.9 rho0_i (a free surface, a splash) are left out, as SPlisHSPlasH does with a
// neighbour count; inside the liquid the correction is two-sided (ours: SPlisHSPlasH corrects
// only converging flow, and a still tank then kept a bouncing mode, measured in docs/PHYSICS.md).
//
// With fluid.divergence_solve "cg" (ours) the same equations are solved by preconditioned
// conjugate gradients instead. The operator A q = -Drho/Dt(-P q) (the density rate of the push of
// q, P the push above) is self-adjoint and positive semi-definite in the inner product
// <a, b> = sum_i c_i a_i b_i with c_i = m_i ("mass") or V_i / rho0_i ("volume"): the push is the
// density rate's transpose in the mass-weighted product of velocities (header above), so
// <q, A q'> = sum_i m_i (P q)_i . (P q')_i. The unknowns are the particles inside the liquid, and
// the body particles that compress at the start of the solve (Jacobi's one-sided bodies, frozen
// for the step); the preconditioner is 1 / D_i (Jacobi's own factor); the same stopping rule and
// cap. One iteration costs what a Jacobi one does (a push and a density-rate sweep) plus two
// ordered dot products. Measured on bench sim's dam break when it came in: 4.9 -> 2.3 divergence
// iterations a step at the same tolerance, about 15 % of a step (since the density solve's
// complementarity stop and the pressure step bound, Jacobi needs 1.6 and the two cost the same).
// Not the default: tried as one, with the gradient correction at 0.02 %, the 0.5 m still tank and
// the Archimedes box of specific gravity 0.7 missed their tests (docs/ACCURACY.md, "A still
// tank"); scenes/jellyfish.json asks for it, with the correction, at 0.01 %.
//
// Walls also carry the hydrostatic part of their pressure (Adami, Hu & Adams 2012 for a wall at
// rest, p_b = p_i + rho0_i g . (x_b - x_i)): its push, -dt sum_b V_b (g . (x_b - x_i)) grad W_ib,
// does not depend on the unknowns and is applied before the constant-density solve. Without it
// a particle at a side wall feels half the vertical pressure gradient the interior does, sinks
// along the wall and drives a circulation that grew every step in a still tank (measured).
//
// Constant-density solve (on v* = v + dt a_nonpressure): the predicted density
// rho*_i = rho_i + dt Drho_i/Dt (with v*) should be rho0_i where the particle is compressed.
// Each iteration sets k_i <- max(0, k_i + w (rho*_i - rho0_i) / (dt^2 D_i)) with w = 1/2 (a
// relaxed, projected Jacobi step as in IISPH, Ihmsen et al. 2014: pressure never pulls, and a
// particle whose predicted density is below rest loses pressure; unrelaxed (w = 1), the
// iteration diverged within a few steps on a still tank, measured) and applies the change; it
// stops when the mean of the complementarity residual (ours: pressure >= 0, rho* = rho0 where it
// is positive, rho* <= rho0 where it is 0), |rho*_i - rho0_i| / rho0_i where the iteration left
// the particle a pressure and max(rho*_i - rho0_i, 0) / rho0_i where it left none, is below
// fluid.max_density_error (%), after at least two iterations (Bender & Koschier 2017, Alg. 3), at
// most max_iterations. (With the compression alone, as the paper counts it, an expanded column,
// its interior below rest density but still under pressure, counted as converged.) It is warm-started with
// each particle's pi = p / rho^2 of the previous step (kept by particle id, so sorting does not
// lose it; k_i = pi_i, or P_i = pi_i rho0_i^2), or with the hydrostatic start's pressure. The
// particles' `pressure` is what both solves applied in the step, p_i = (pi_i + q_i / dt) rho_i^2
// with q the divergence solve's total (its impulse over the step): in a still tank the
// hydrostatic load moves from the density solve into the divergence solve's warm-started q.
//
// Kernel: the cubic spline for the density sum and every gradient (kernels.h). Each neighbour
// pair's W'(r)/r is computed once per step, by the density pass alongside the neighbour lists
// (NeighborLists::slopes: it has r at hand), and every iteration forms grad W_ij from it and the
// positions (which the solves do not move): one float a pair instead of a stored gradient's
// three, and the same floats. Error sums
// reduce per fixed chunk of particles, then over chunks in order: the result does not depend on
// the number of threads.
#pragma once

#include "sim/solvers/pressure_solver.h"
#include "sim/solvers/solver_common.h"

namespace kurage::sim {

inline constexpr const char* kDfsphSummary =
    "'dfsph' (divergence-free SPH, Bender & Koschier 2017: incompressible to max_density_error, whatever the step; "
    "uses the cubic spline kernel, support_radius 2 recommended; 3 closer to Martin & Moyce in a deep slice, at "
    "about 2.5 times the cost, docs/VALIDATION.md)";

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
  uint64_t steps = 0;                     // steps the solver ran
  uint64_t densityIterations = 0;         // summed over steps
  uint64_t divergenceIterations = 0;
  int maxDensityIterations = 0;           // largest in one step
  int maxDivergenceIterations = 0;
  uint64_t densityCapHits = 0;            // steps that stopped at the iteration cap
  uint64_t divergenceCapHits = 0;
  double lastDensityError = 0.0;          // the last step's final mean error, fraction of rho0
  double lastDivergenceError = 0.0;
  double maxDensityError = 0.0;           // largest final mean density error of any step
  double sumDensityError = 0.0;           // summed over steps (mean = sum / steps)
  uint64_t tornSteps = 0;                 // steps that left torn body particles out (SolverContext::unsolved)
  int maxTorn = 0;                        // most torn body particles left out in one step
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
  // the unknowns to qSum_; returns the iterations and sets `error`.
  int divergenceCg(const SolverContext& c, double& error);
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
  // Y = w_j k_j L_j (x_j - origin_): 36 bytes a neighbour, where L_j's three rows took 48.
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
