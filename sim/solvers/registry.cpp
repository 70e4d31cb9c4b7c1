// The pressure solvers' registry: one line per solver (sim/solvers/pressure_solver.h).
#include "sim/solvers/dfsph.h"
#include "sim/solvers/pressure_solver.h"
#include "sim/solvers/wcsph.h"

#include <functional>
#include <stdexcept>
#include <utility>

namespace kurage::sim {

namespace {
using Factory = std::function<std::unique_ptr<PressureSolver>(const FluidParams&)>;
const std::vector<std::pair<std::string, Factory>>& registry() {
  static const std::vector<std::pair<std::string, Factory>> table{
      {"wcsph", [](const FluidParams& f) { return std::make_unique<WcsphSolver>(f); }},
      {"dfsph", [](const FluidParams& f) { return std::make_unique<DfsphSolver>(f); }},
  };
  return table;
}
}  // namespace

const std::vector<std::string>& pressureSolverNames() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> n;
    for (const auto& [name, factory] : registry()) n.push_back(name);
    return n;
  }();
  return names;
}

std::unique_ptr<PressureSolver> makePressureSolver(const FluidParams& fluid) {
  for (const auto& [name, factory] : registry())
    if (name == fluid.solver) return factory(fluid);
  throw std::invalid_argument("unknown pressure solver '" + fluid.solver + "'");
}

DensityKernel densityKernelOf(const FluidParams& fluid) { return makePressureSolver(fluid)->densityKernel(); }

std::string boundaryCouplingProblem(const FluidParams& fluid) {
  if (!makePressureSolver(fluid)->couplesBoundaryBodies())
    return "\"boundary\" needs a solver that couples bodies as the fluid's boundary (fluid.solver \"dfsph\"), got \"" +
           fluid.solver + "\"";
  if (fluid.densitySum != DensitySum::Volume)
    return "\"boundary\" needs fluid.density_sum \"volume\": the fluid counts a boundary sample by its volume "
           "m / rho0, which (10) grows as the body stretches";
  if (fluid.divergenceSolve != DivergenceSolve::Jacobi)
    return "\"boundary\" needs fluid.divergence_solve \"jacobi\": spreading the reactions over spring patches "
           "makes the solves' operator unsymmetric, which conjugate gradients does not allow";
  return "";
}

SphKernel resolvedKernel(const FluidParams& fluid, WallDensity walls) {
  if (fluid.kernel != SphKernel::Auto) return fluid.kernel;
  if (densityKernelOf(fluid) == DensityKernel::CubicSpline || walls == WallDensity::BoundaryParticles)
    return SphKernel::CubicSpline;
  return SphKernel::Mueller2003;
}

}  // namespace kurage::sim
