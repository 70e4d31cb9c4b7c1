// The simulation frame by frame, for the run's report (pipeline/report): after each frame, the
// steps taken since the frame before and their mean size, the bound that limited most of them,
// the mean compression the density pass measured (sim::SimStats), each of the pressure solver's
// solves' iterations per step and cap hits, the bodies' collision cap hits, the particle count
// (emitters and sinks change it) and the kinetic energy of every particle. The sim stage records
// after every frame and writes OUT/sim_frames.csv, one row per frame from frame 0:
//   frame, time_s, steps, mean_step_s, step_bound, mean_density_error (a fraction of rho0),
//   SOLVE_iterations_per_step, SOLVE_cap_hits (for each solve of an iterative solver, e.g.
//   density, divergence), collision_cap_hits (with bodies), particles, kinetic_energy_J
// Frame 0 (t = 0) has no steps: its per-step fields are empty. The rows are a function of the
// scene: a run resumed from a checkpoint (which keeps them) writes the same file bit for bit.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace kurage::sim {
class Simulation;
}

namespace kurage::pipeline {

class SimSeries {
public:
  // The solves and bodies of `simulation`'s scene; `frameCount`: the most rows a checkpoint may hold.
  SimSeries(const sim::Simulation& simulation, int frameCount);

  // One row at the simulation's time.
  void record(const sim::Simulation& simulation);
  size_t size() const { return rows_.size(); }

  // The rows so far, for checkpoints (pipeline/io/checkpoint.h).
  std::string saveState() const;
  // Throws sim::StateError for rows that do not fit.
  void restoreState(const std::string& bytes);

  // The file's text, and OUT/sim_frames.csv written atomically.
  std::string csv() const;
  void write(const std::filesystem::path& outDir) const;

private:
  // Totals since t = 0 at a frame; the file's per-frame figures are differences of two rows.
  struct Row {
    double time = 0.0;
    uint64_t steps = 0;
    double densityErrorSum = 0.0;
    std::vector<uint64_t> boundCounts;  // per sim::StepBound
    std::vector<uint64_t> iterations;   // per solve (solveNames_)
    std::vector<uint64_t> capHits;      // per solve
    uint64_t collisionCapHits = 0;
    uint64_t particles = 0;
    double kineticEnergy = 0.0;  // at the frame, J
  };
  int frameCount_ = 0;
  std::vector<std::string> solveNames_;
  bool bodies_ = false;
  std::vector<Row> rows_;
};

}  // namespace kurage::pipeline
