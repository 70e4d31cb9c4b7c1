// The bodies of a run, frame by frame: each body's centre of mass and mean rest-density factor
// (its stretch), each muscle's force as applied in the last step, the fluid's surface height
// (the 98th percentile of the fluid particles' heights), and for each shell body (a jellyfish's
// bell, pipeline/analysis/shell_wall.h) its margin radius, the fluid particles inside its wall,
// its tilt, apex height and diameter. The sim stage records after every frame and writes
// OUT/bodies.csv, and OUT/bodies.png where the scene has muscles (the muscles' force and each
// body's depth against time, the paper's Fig. 3); run.json gets each shell's summary.
// In a scene with emitters each row holds the water's level too (waterLevel,
// pipeline/analysis/still_tank.h: the water's volume per floor area, read where it ends), and
// run.json gets each pour's account (pourSummary). Metres, seconds, newtons, degrees.
#pragma once

#include "pipeline/analysis/shell_wall.h"
#include "pipeline/analysis/still_tank.h"
#include "sim/params.h"

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace kurage::sim {
class Simulation;
}

namespace kurage::pipeline {

class BodyTrack {
public:
  // `params`: the scene's simulation (it must outlive the track); `frameCount`: the most rows a
  // checkpoint may hold.
  BodyTrack(const sim::SimParams& params, std::string sceneName, int frameCount);

  // The shells as built: call with the simulation at t = 0, before any record.
  void start(const sim::Simulation& simulation);
  // One row at the simulation's time (nothing for a scene without bodies or emitters).
  void record(const sim::Simulation& simulation);

  // One record: the simulation's time, the fluid's surface height, and per body, per muscle (in
  // the scene's order, body by body) and per shell body its measures.
  struct Row {
    double time = 0.0;
    double surface = 0.0;
    double level = 0.0;  // the water's level (scenes with emitters; 0 otherwise)
    double displaced = 0.0;  // what the bodies take of it (bodiesDisplacement; scenes with emitters)
    double volume = 0.0;     // the bodies' own volume, sum of m_i / rho0_i over their particles (m^3)
    std::vector<Eigen::Vector3d> centres;  // per body: its centre of mass (particle-mass weighted)
    std::vector<double> factors;           // per body: mean rest-density factor
    std::vector<double> forces;            // per muscle: as applied in the last step (at t = 0 the curve's)
    std::vector<double> margins;  // per shell body: margin radius (m)
    std::vector<size_t> inWall;   // per shell body: fluid particles inside its wall
    std::vector<double> tilts;    // per shell body: tilt from its axis as built (degrees)
    std::vector<double> apexes;   // per shell body: height of its highest particle (m)
    std::vector<double> widths;   // per shell body: its diameter (ShellWall::shape, m)
  };
  // The rows recorded so far, oldest first.
  const std::vector<Row>& rows() const { return rows_; }

  // The rows so far, for checkpoints (pipeline/io/checkpoint.h).
  std::string saveState() const;
  // Throws sim::StateError for rows that do not fit the scene.
  void restoreState(const std::string& bytes);

  // Per shell body, for run.json: the margin radius at rest (t = 0) and its smallest value, and
  // the most fluid particles found inside the wall in a frame (ShellWall::fluidInsideWall);
  // null for another body.
  nlohmann::json shellSummary(size_t body) const;

  // Per emitter, for run.json: its pour against the nozzle's flow and the level's settled rise.
  // - nozzle_volume_m3 = pi r^2 v (min(end, t_run) - start); emitted_volume_m3 = its particles
  //   times m / rho0 (the water they make at rest density);
  // - the level's rise from the pour's start to the last row before the next pour starts (or the
  //   run's end), each the level's mean over the rows of a window before it (waves and a swimming
  //   body's breathing move one frame's by 0.1 m in scenes/jellyfish.json): 3 s, or with a pulsed
  //   muscle whole periods of its pulses, at least 3 s and none before the pulses start where a
  //   whole period fits after them (a body at rest displaces otherwise, and the start's transient
  //   is over), against emitted_volume / container floor area (a pour that overlaps another, or
  //   ends too near the next, counts the other's water too); and the same of the water's own level
  //   (the level less what the bodies take of it, bodiesDisplacement): the pour's water, which a
  //   bell whose pulses fade between the windows does not move; and the bodies' own volume in each
  //   window (the mean of Row::volume);
  // - each shell body's horizontal drift over the pour (start to end) and whether it is away from
  //   the nozzle (drift . (centre - nozzle) > 0, horizontally, at the start).
  // Null without emitters or rows.
  nlohmann::json pourSummary(const sim::Simulation& simulation) const;

  // OUT/bodies.csv, and OUT/bodies.png (with .svg, .pdf, .gp) when the scene has muscles.
  void write(const std::filesystem::path& outDir) const;

private:
  // The swimming speed of a shell with a pulsed muscle (its first), in bell diameters per pulse:
  // the net rise of its apex from the first pulse's start to the end of its tenth period (or of
  // the last whole period recorded), over the pulses, over the diameter at rest.
  nlohmann::json swimSummary(size_t body, size_t k) const;
  // The muscles' force against time, with each body's measured depth below the free surface.
  void writePlot(const std::filesystem::path& file) const;

  const sim::SimParams& params_;
  std::string sceneName_;
  int frameCount_ = 0;
  std::vector<std::optional<ShellWall>> walls_;  // per body; shells only
  std::vector<Row> rows_;
};

}  // namespace kurage::pipeline
