// The pressure solvers' registry: one line per solver (sim/solvers/pressure_solver.h).
#include "sim/solvers/dfsph/dfsph.h"
#include "sim/solvers/iisph/iisph.h"
#include "sim/solvers/pressure_solver.h"
#include "sim/solvers/wcsph/wcsph.h"

#include <functional>
#include <stdexcept>
#include <utility>

namespace kurage::sim {

namespace {
struct Entry {
  std::string name;
  std::string summary;  // fluid.solver's documentation of it
  std::function<std::unique_ptr<SolverParams>()> params;
  std::function<std::unique_ptr<PressureSolver>(const FluidParams&)> solver;
};

template <class Solver, class Params>
Entry entry(const char* name, const char* summary) {
  return {name, summary, [] { return std::make_unique<Params>(); },
          [](const FluidParams& f) { return std::make_unique<Solver>(f); }};
}

const std::vector<Entry>& registry() {
  static const std::vector<Entry> table{
      entry<WcsphSolver, WcsphParams>("wcsph", kWcsphSummary),
      entry<DfsphSolver, DfsphParams>("dfsph", kDfsphSummary),
      entry<IisphSolver, IisphParams>("iisph", kIisphSummary),
  };
  return table;
}

const Entry& find(const std::string& name) {
  for (const Entry& e : registry())
    if (e.name == name) return e;
  throw std::invalid_argument("unknown pressure solver '" + name + "'");
}
}  // namespace

const std::vector<std::string>& pressureSolverNames() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> n;
    for (const Entry& e : registry()) n.push_back(e.name);
    return n;
  }();
  return names;
}

const std::vector<std::string>& pressureSolverSummaries() {
  static const std::vector<std::string> summaries = [] {
    std::vector<std::string> s;
    for (const Entry& e : registry()) s.push_back(e.summary);
    return s;
  }();
  return summaries;
}

std::unique_ptr<SolverParams> makeSolverParams(const std::string& name) { return find(name).params(); }

std::unique_ptr<PressureSolver> makePressureSolver(const FluidParams& fluid) {
  return find(fluid.solver.name()).solver(fluid);
}

DensityKernel densityKernelOf(const FluidParams& fluid) { return makePressureSolver(fluid)->densityKernel(); }

std::optional<ParamProblem> pressureSolverProblem(const FluidParams& fluid) { return fluid.solver.params().problem(fluid); }

std::string boundaryCouplingProblem(const FluidParams& fluid) {
  const std::unique_ptr<PressureSolver> solver = makePressureSolver(fluid);
  if (solver->couplesBoundaryBodies()) return solver->boundaryCouplingProblem(fluid);
  std::string coupling;
  for (const Entry& e : registry()) {
    FluidParams other;  // the defaults: a solver that refuses the scene's other settings still answers
    other.solver = SolverChoice(e.name);
    if (e.solver(other)->couplesBoundaryBodies()) coupling += (coupling.empty() ? "\"" : ", \"") + e.name + "\"";
  }
  return "\"boundary\" needs a solver that couples bodies as the fluid's boundary (fluid.solver " + coupling +
         "), got \"" + fluid.solver.name() + "\"";
}

SphKernel resolvedKernel(const FluidParams& fluid, WallDensity walls) {
  if (fluid.kernel != SphKernel::Auto) return fluid.kernel;
  return makePressureSolver(fluid)->ownKernel(walls);
}

uint64_t SolverCounters::iterations() const {
  uint64_t n = 0;
  for (const SolveCount& s : solves) n += s.iterations;
  return n;
}

uint64_t SolverCounters::capHits() const {
  uint64_t n = 0;
  for (const SolveCount& s : solves) n += s.capHits;
  return n;
}

// fluid.solver (sim/params.h)
SolverChoice::SolverChoice(const char* name) : SolverChoice(std::string(name)) {}
SolverChoice::SolverChoice(const std::string& name) : name_(name), params_(makeSolverParams(name)) {}
SolverChoice::SolverChoice(const SolverChoice& other) : name_(other.name_), params_(other.params_->clone()) {}
SolverChoice::SolverChoice(SolverChoice&& other) noexcept = default;
SolverChoice& SolverChoice::operator=(const SolverChoice& other) {
  if (this != &other) {
    params_ = other.params_->clone();
    name_ = other.name_;
  }
  return *this;
}
SolverChoice& SolverChoice::operator=(SolverChoice&& other) noexcept = default;
SolverChoice::~SolverChoice() = default;

}  // namespace kurage::sim
