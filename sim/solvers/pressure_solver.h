// The pressure solver seam: how the fluid's pressure is found each step. The step order is
// written once, in Simulation (sim/simulation.h), and names no solver; a solver plugs into it at
// two points and says, through needs(), what the step must compute for it:
//
//   sort, walls' sums (the lift and wall-weight gradients when needs().wallSums), telescopic
//   rest density, density (with the solver's kernel), L_i (needs().gradientCorrection)
//   -> afterDensity():       WCSPH: p from the equation of state (4); DFSPH: its factors and
//                            the divergence solve on v; IISPH: nothing
//   -> non-pressure forces (viscosity, gravity; -grad p / rho too when needs().pressureForce),
//      springs, muscles; v* = v + a dt
//   -> correctVelocities():  when needs().correctsVelocities: DFSPH's and IISPH's
//                            constant-density solves on v*
//   -> x = x + v dt, pins, collisions, walls, emitters, sinks
//
// A solver is a folder, sim/solvers/<name>/: the solver (PressureSolver), its parameters
// (SolverParams, with their describe(), so the scene loader, scenes/schema.json and run.json
// follow), its hydrostatic start, its walls' needs, its report for run.json and its checkpoint
// state. Adding one is that folder and one line in registry.cpp's table (and its source in
// sim/CMakeLists.txt); fluid.solver then accepts its name (docs/design/physics.md, "Pressure solvers").
#pragma once

#include "sim/kernels.h"
#include "sim/neighbor_grid.h"
#include "sim/param_visitor.h"
#include "sim/params.h"
#include "sim/particles.h"
#include "sim/state.h"

#include <Eigen/Core>

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

namespace kurage::sim {

namespace solvers {
struct LaneLists;  // sweeps.h
}

// The bodies coupled as the fluid's boundary (BodyCoupling::Boundary; sim/solvers/dfsph/dfsph.h),
// by sorted particle index (BodySystem::boundaryPatches; rebuilt after every sort).
struct BoundaryBodies {
  std::vector<uint8_t> sample;    // per particle: 1 for a particle of such a body (a held one too)
  std::vector<uint32_t> offsets;  // per particle + 1: particle i's patch is patch[offsets[i], offsets[i + 1])
  std::vector<uint32_t> patch;    // the particle itself and its spring neighbours (empty for others)
  std::vector<float> share;       // per particle: m_i over the sum of its patch's masses
  bool empty() const { return patch.empty(); }
};

// What a solver sees of the step: the sorted particles, their neighbours (found by the density
// pass, |r_ij| < h) and the walls' sums: from boundary particles, or, for a solver whose needs()
// ask for them, from the wall weights' tables (null when the walls have neither).
// Asked between the passes of long work (Simulation::setStopChecks): true ends it early.
using StopCheck = std::function<bool()>;

struct SolverContext {
  ParticleSet& particles;
  const NeighborLists& neighbors;
  const FluidParams& fluid;
  float supportRadius = 1.0f;                 // h, m
  const float* boundaryVolume = nullptr;      // per particle: sum_b V_b W_ib (density kernel)
  const float* boundaryGradient = nullptr;    // per particle, 3 floats: sum_b V_b grad W_ib
  const float* boundaryLift = nullptr;        // per particle, 3 floats: sum_b V_b (g . (x_b - x_i)) grad W_ib
  const float* gradientCorrection = nullptr;  // per particle, 6 floats: L_i (fluid.h), or null
  // Per particle, an UnsolvedState (sim/particles.h): kHeld where a pin holds a body particle in
  // place this step (its velocity is not the solver's to change), kTorn where a telescopic body
  // is torn, kBoundary for a body coupled as the fluid's boundary; null when the bodies have
  // none of these.
  const uint8_t* unsolved = nullptr;
  const BoundaryBodies* boundaryBodies = nullptr;  // null when no body is coupled as a boundary
  float lastStep = 0.0f;                      // the previous step, s (0 before the first)
  Eigen::Vector3f gravity{0.0f, 0.0f, 0.0f};  // g, m/s^2
  // Asked once per iteration of a solve: true ends the solve there, and *cutShort is set (the
  // step's state is then only fit to be thrown away). Null: never asked.
  const StopCheck* stop = nullptr;
  bool* cutShort = nullptr;
  bool stopRequested() const {
    if (!stop || !*stop || !(*stop)()) return false;
    if (cutShort) *cutShort = true;
    return true;
  }
};

// A combination of parameters a solver cannot run, naming the scene key to change.
struct ParamProblem {
  std::string key;  // JSON path from the scene's top, e.g. "fluid.kernel"
  std::string message;
};

// A solver's own parameters: scene keys of the `fluid` object, read only when fluid.solver names
// the solver (two solvers may declare the same key, with the same type and default).
class SolverParams {
public:
  virtual ~SolverParams() = default;
  virtual std::unique_ptr<SolverParams> clone() const = 0;
  virtual void describe(ParamVisitor& v) = 0;
  // Why these parameters cannot run with the rest of the fluid's, or nothing.
  virtual std::optional<ParamProblem> problem(const FluidParams& /*fluid*/) const { return std::nullopt; }
};

// What a solver asks of the step around it (constant over a run).
struct StepNeeds {
  bool pressureForce = false;       // the force pass adds -grad p / rho from the p_i afterDensity set
  bool correctsVelocities = false;  // correctVelocities runs on v* (a constant-density solve)
  bool wallSums = false;            // the walls' hydrostatic sums (boundaryLift) and, with wall weights,
                                    // their gradient sums from the tables, in the context
  bool gradientCorrection = false;  // with fluid.gradient_correction: L_i in the context (the force pass
                                    // corrects its own pressure force otherwise)
  // Walls of boundary particles: a fluid particle nearer than penaltyRest to a wall plane is
  // pushed back with penaltyStiffness (penaltyRest - d) per unit mass (0: none; fluid.h WallSums).
  float wallPenaltyStiffness = 0.0f;  // 1/s^2
  float wallPenaltyRest = 0.0f;       // m
};

// Iterations of each of a solver's solves, summed over the run (for studies and benchmarks that
// compare solvers; each solver's report has the rest).
struct SolveCount {
  std::string name;  // e.g. "density", "divergence"
  uint64_t iterations = 0;
  uint64_t capHits = 0;  // solves stopped at their iteration cap
};
struct SolverCounters {
  uint64_t steps = 0;  // steps the solver ran
  std::vector<SolveCount> solves;
  uint64_t iterations() const;  // over every solve
  uint64_t capHits() const;
};

// A solver's account of its run, for run.json (stages.sim.solver): named values in order; a '.'
// in a key nests it ("density_solve.cap").
struct SolverReport {
  using Value = std::variant<double, int64_t, std::string>;
  std::vector<std::pair<std::string, Value>> entries;
  void add(std::string key, double v) { entries.emplace_back(std::move(key), v); }
  void add(std::string key, int64_t v) { entries.emplace_back(std::move(key), v); }
  void add(std::string key, uint64_t v) { add(std::move(key), int64_t(v)); }
  void add(std::string key, int v) { add(std::move(key), int64_t(v)); }
  void add(std::string key, std::string v) { entries.emplace_back(std::move(key), std::move(v)); }
  void add(std::string key, const char* v) { add(std::move(key), std::string(v)); }
};

// Something the user should know about a run (kurage sim prints it), with the report key that
// has the figures ("" for the report itself).
struct SolverWarning {
  std::string message;
  std::string reportKey;
};

class PressureSolver {
public:
  virtual ~PressureSolver() = default;
  virtual std::string_view name() const = 0;
  // The kernel of the density sum (3) and of the solver's own gradients.
  virtual DensityKernel densityKernel() const = 0;
  // fluid.kernel "auto" with these walls.
  virtual SphKernel ownKernel(WallDensity walls) const = 0;
  // True for a solver without a speed of sound (the CFL bound then uses |v| and the spacing).
  virtual bool incompressible() const = 0;
  virtual StepNeeds needs() const = 0;
  // True for a solver that couples bodies as the fluid's boundary (BodyCoupling::Boundary), and
  // then what else that needs of the fluid's parameters, naming the key ("" when nothing).
  virtual bool couplesBoundaryBodies() const { return false; }
  virtual std::string boundaryCouplingProblem(const FluidParams& /*fluid*/) const { return ""; }
  // After the density pass.
  virtual void afterDensity(const SolverContext& context) = 0;
  // After v* = v + a dt, before positions move (when needs().correctsVelocities).
  virtual void correctVelocities(const SolverContext& /*context*/, float /*dt*/) {}
  // A hydrostatic start (fluid.initial_state "hydrostatic", gravity g along -z): first the
  // fluid blocks' lattice points before particles are made of them, each block's free surface at
  // tops[b] (the solver may move them: WCSPH compresses each column); then each fluid particle's
  // hydrostatic head g (top - z), m^2/s^2 (its pressure over rho0), by particle id, 0 for ids
  // that are no fluid particle (a solver that keeps pressure from step to step starts from it).
  virtual void hydrostaticLattice(std::vector<std::vector<Eigen::Vector3f>>& /*blocks*/,
                                  const std::vector<float>& /*tops*/, float /*g*/) const {}
  virtual void hydrostaticHead(const std::vector<float>& /*headById*/) {}
  virtual SolverCounters counters() const = 0;
  virtual void report(SolverReport& /*out*/) const {}
  virtual std::vector<SolverWarning> warnings() const { return {}; }
  virtual size_t memoryBytes() const { return 0; }
  // This step's interleaved neighbour lists (solvers/sweeps.h's lanes path) where the solver built
  // them from this step's density pass (the force pass then sums its viscosity on them); null otherwise.
  virtual const solvers::LaneLists* laneLists() const { return nullptr; }
  // What the solver carries from step to step (its statistics, a warm start), for checkpoints.
  virtual void saveState(StateWriter& out) const = 0;
  virtual void restoreState(StateReader& in) = 0;
};

// The registry: names accepted by fluid.solver, each with a line for the key's documentation.
const std::vector<std::string>& pressureSolverNames();
const std::vector<std::string>& pressureSolverSummaries();
// A solver's parameters at their defaults; throws std::invalid_argument for an unknown name.
std::unique_ptr<SolverParams> makeSolverParams(const std::string& name);
// The solver of a scene's parameters.
std::unique_ptr<PressureSolver> makePressureSolver(const FluidParams& fluid);
// The density kernel of the scene's solver (for mass calibration before a solver exists).
DensityKernel densityKernelOf(const FluidParams& fluid);
// Why the fluid's parameters cannot run under its solver, naming the key; nothing when they can.
std::optional<ParamProblem> pressureSolverProblem(const FluidParams& fluid);
// Why bodies cannot be coupled as the fluid's boundary (BodyCoupling::Boundary) under these fluid
// parameters, naming the key to change; empty when they can.
std::string boundaryCouplingProblem(const FluidParams& fluid);
// fluid.kernel with "auto" resolved: the solver's own kernel for these walls.
SphKernel resolvedKernel(const FluidParams& fluid, WallDensity walls);

}  // namespace kurage::sim
