#include "pipeline/analysis/sim_series.h"

#include "pipeline/io/csv.h"
#include "pipeline/io/files.h"
#include "sim/simulation.h"

#include <cstdio>
#include <sstream>

namespace kurage::pipeline {

namespace {

// Each solve of the pressure solver with its running totals (none for a solver without solves).
std::vector<sim::SolveCount> solveTotals(const sim::Simulation& simulation) { return simulation.solver().counters().solves; }

std::string number(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.9g", v);
  return buffer;
}

}  // namespace

SimSeries::SimSeries(const sim::Simulation& simulation, int frameCount)
    : frameCount_(frameCount), bodies_(simulation.bodies() != nullptr) {
  for (const sim::SolveCount& s : solveTotals(simulation)) solveNames_.push_back(s.name);
}

void SimSeries::record(const sim::Simulation& simulation) {
  const sim::SimStats& stats = simulation.stats();
  Row row;
  row.time = simulation.time();
  row.steps = stats.steps;
  row.densityErrorSum = stats.densityErrorSum;
  row.boundCounts.assign(stats.boundCounts.begin(), stats.boundCounts.end());
  for (const sim::SolveCount& s : solveTotals(simulation)) {
    row.iterations.push_back(s.iterations);
    row.capHits.push_back(s.capHits);
  }
  if (const sim::BodySystem* bodies = simulation.bodies()) row.collisionCapHits = bodies->stats().capHits;
  row.particles = simulation.particles().size();
  row.kineticEnergy = sim::kineticEnergy(simulation.particles());
  rows_.push_back(std::move(row));
}

std::string SimSeries::saveState() const {
  sim::StateWriter out;
  out.value(uint64_t(rows_.size()));
  for (const Row& r : rows_) {
    out.value(r.time);
    out.value(r.steps);
    out.value(r.densityErrorSum);
    out.array(r.boundCounts);
    out.array(r.iterations);
    out.array(r.capHits);
    out.value(r.collisionCapHits);
    out.value(r.particles);
    out.value(r.kineticEnergy);
  }
  return out.take();
}

void SimSeries::restoreState(const std::string& bytes) {
  sim::StateReader in(bytes);
  const uint64_t count = in.value<uint64_t>();
  if (count > uint64_t(frameCount_)) throw sim::StateError("checkpoint state: more frame records than frames");
  std::vector<Row> rows(static_cast<size_t>(count));
  for (Row& r : rows) {
    r.time = in.value<double>();
    r.steps = in.value<uint64_t>();
    r.densityErrorSum = in.value<double>();
    in.arrayOf(r.boundCounts, size_t(sim::StepBound::Count));
    in.arrayOf(r.iterations, solveNames_.size());
    in.arrayOf(r.capHits, solveNames_.size());
    r.collisionCapHits = in.value<uint64_t>();
    r.particles = in.value<uint64_t>();
    r.kineticEnergy = in.value<double>();
  }
  if (!in.done()) throw sim::StateError("checkpoint state: bytes left over after the frame records");
  rows_ = std::move(rows);
}

std::string SimSeries::csv() const {
  std::ostringstream csv;
  csv << "frame,time_s,steps,mean_step_s,step_bound,mean_density_error";
  for (const std::string& s : solveNames_) csv << "," << s << "_iterations_per_step," << s << "_cap_hits";
  if (bodies_) csv << ",collision_cap_hits";
  csv << ",particles,kinetic_energy_J\n";
  for (size_t f = 0; f < rows_.size(); ++f) {
    const Row& r = rows_[f];
    const Row* before = f > 0 ? &rows_[f - 1] : nullptr;
    const uint64_t steps = before ? r.steps - before->steps : r.steps;
    const auto perStep = [&](double total) { return steps ? number(total / double(steps)) : std::string(); };
    csv << f << "," << number(r.time) << "," << steps << ","
        << perStep(before ? r.time - before->time : r.time) << ",";
    // The bound that limited most of the frame's steps.
    size_t most = 0;
    uint64_t mostCount = 0;
    for (size_t b = 0; b < r.boundCounts.size(); ++b) {
      const uint64_t n = r.boundCounts[b] - (before ? before->boundCounts[b] : 0);
      if (n > mostCount) most = b, mostCount = n;
    }
    if (mostCount) csv << csvField(std::string(sim::stepBoundName(sim::StepBound(most))));
    csv << "," << perStep(r.densityErrorSum - (before ? before->densityErrorSum : 0.0));
    for (size_t s = 0; s < solveNames_.size(); ++s)
      csv << "," << perStep(double(r.iterations[s] - (before ? before->iterations[s] : 0))) << ","
          << r.capHits[s] - (before ? before->capHits[s] : 0);
    if (bodies_) csv << "," << r.collisionCapHits - (before ? before->collisionCapHits : 0);
    csv << "," << r.particles << "," << number(r.kineticEnergy) << "\n";
  }
  return csv.str();
}

void SimSeries::write(const std::filesystem::path& outDir) const { writeTextAtomic(outDir / "sim_frames.csv", csv()); }

}  // namespace kurage::pipeline
