// Helpers shared by the simulation tests: a particle set's kinetic energy, its positions by id,
// a plain box body, a solver's keys set as a scene sets them, and what a solver reports.
#pragma once

#include "sim/params.h"
#include "sim/particles.h"
#include "sim/simulation.h"
#include "sim/solvers/dfsph/dfsph.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <variant>

#include <Eigen/Core>

#include <algorithm>
#include <array>
#include <vector>

namespace kurage::test {

// Sum of m v^2 / 2 over every particle, J.
using sim::kineticEnergy;

// (id, x, y, z) of every particle, sorted by id: two runs compared whatever their particles' order.
inline std::vector<std::array<float, 4>> positionsById(const sim::ParticleSet& p) {
  std::vector<std::array<float, 4>> out;
  for (size_t i = 0; i < p.size(); ++i) out.push_back({float(p.id[i]), p.x[i], p.y[i], p.z[i]});
  std::sort(out.begin(), out.end());
  return out;
}

// The statistics of a simulation run by DFSPH.
inline const sim::DfsphStats& dfsphStats(const sim::Simulation& s) {
  return dynamic_cast<const sim::DfsphSolver&>(s.solver()).stats();
}

// The solver's own keys of `fluid` (fluid.max_density_error, ...) from JSON values, through its
// describe() (setSolverKeys below).
class SolverKeySetter final : public sim::ParamVisitor {
public:
  explicit SolverKeySetter(const nlohmann::json& keys) : keys_(keys) {}
  void value(const char* key, float& ref, const sim::Field&) override { set(key, ref); }
  void value(const char* key, int& ref, const sim::Field&) override { set(key, ref); }
  void value(const char* key, bool& ref, const sim::Field&) override { set(key, ref); }
  void choice(const char* key, size_t& index, const std::vector<const char*>& names, const sim::Field&) override {
    if (!keys_.contains(key)) return;
    for (size_t k = 0; k < names.size(); ++k)
      if (keys_[key] == names[k]) {
        index = k;
        ++used;
        return;
      }
    throw std::invalid_argument(std::string(key) + ": no such value");
  }
  size_t used = 0;  // keys set

private:
  template <class T>
  void set(const char* key, T& ref) {
    if (!keys_.contains(key)) return;
    ref = keys_[key].get<T>();
    ++used;
  }
  const nlohmann::json& keys_;
};

// Sets the solver's own keys as a scene sets them; a key the solver does not declare is
// std::invalid_argument.
inline void setSolverKeys(sim::FluidParams& fluid, const nlohmann::json& keys) {
  SolverKeySetter setter(keys);
  fluid.solver.params().describe(setter);
  if (setter.used != keys.size()) throw std::invalid_argument("a key fluid.solver \"" + fluid.solver.name() + "\" lacks");
}

// A solve's counts by name (sim::SolverCounters; "density" for the constant-density solve of
// DFSPH and IISPH), zeros when the solver has no such solve.
inline sim::SolveCount solveCount(const sim::Simulation& s, const std::string& name) {
  for (const sim::SolveCount& c : s.solver().counters().solves)
    if (c.name == name) return c;
  return {name, 0, 0};
}

// A number of the solver's report (run.json's stages.sim.solver) by its key, NaN when it has none.
inline double reportNumber(const sim::Simulation& s, const std::string& key) {
  sim::SolverReport report;
  s.solver().report(report);
  for (const auto& [k, v] : report.entries)
    if (k == key) {
      if (const double* d = std::get_if<double>(&v)) return *d;
      if (const int64_t* i = std::get_if<int64_t>(&v)) return double(*i);
    }
  return std::numeric_limits<double>::quiet_NaN();
}

// A box-shaped body named "box" over [min, max], every other parameter at its default.
inline sim::BodyParams boxBody(const Eigen::Vector3f& min, const Eigen::Vector3f& max) {
  sim::BodyParams b;
  b.name = "box";
  b.shape = sim::BodyShape::Box;
  b.min = min;
  b.max = max;
  return b;
}

}  // namespace kurage::test
