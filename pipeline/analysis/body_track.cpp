#include "pipeline/analysis/body_track.h"

#include "pipeline/io/files.h"
#include "pipeline/io/plot.h"
#include "sim/simulation.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>

namespace kurage::pipeline {

namespace fs = std::filesystem;

BodyTrack::BodyTrack(const sim::SimParams& params, std::string sceneName, int frameCount)
    : params_(params), sceneName_(std::move(sceneName)), frameCount_(frameCount) {}

void BodyTrack::start(const sim::Simulation& simulation) {
  const sim::ParticleSet& p = simulation.particles();
  walls_.clear();
  for (size_t b = 0; b < params_.bodies.size(); ++b)
    walls_.push_back(params_.bodies[b].shape == sim::BodyShape::Shell
                         ? std::optional<ShellWall>(std::in_place, params_.bodies[b], int(b + 1), p,
                                                    params_.fluid.spacing)
                         : std::nullopt);
}

std::string BodyTrack::saveState() const {
  sim::StateWriter out;
  out.value(uint64_t(rows_.size()));
  for (const Row& r : rows_) {
    out.value(r.time);
    out.value(r.surface);
    out.value(r.level);
    out.value(r.displaced);
    out.value(r.volume);
    std::vector<double> centres;
    for (const Eigen::Vector3d& c : r.centres) centres.insert(centres.end(), {c.x(), c.y(), c.z()});
    out.array(centres);
    out.array(r.factors);
    out.array(r.forces);
    out.array(r.margins);
    out.array(std::vector<uint64_t>(r.inWall.begin(), r.inWall.end()));
    out.array(r.tilts);
    out.array(r.apexes);
    out.array(r.widths);
  }
  return out.take();
}

void BodyTrack::restoreState(const std::string& bytes) {
  sim::StateReader in(bytes);
  const uint64_t count = in.value<uint64_t>();
  if (count > uint64_t(frameCount_))
    throw sim::StateError("checkpoint state: more body records than frames");
  const size_t bodies = params_.bodies.size();
  size_t muscles = 0, shells = 0;
  for (const sim::BodyParams& b : params_.bodies) {
    muscles += b.muscles.size();
    shells += b.shape == sim::BodyShape::Shell;
  }
  std::vector<Row> rows(static_cast<size_t>(count));
  for (Row& r : rows) {
    r.time = in.value<double>();
    r.surface = in.value<double>();
    r.level = in.value<double>();
    r.displaced = in.value<double>();
    r.volume = in.value<double>();
    std::vector<double> centres;
    in.arrayOf(centres, 3 * bodies);
    for (size_t b = 0; b < bodies; ++b) r.centres.emplace_back(centres[3 * b], centres[3 * b + 1], centres[3 * b + 2]);
    in.arrayOf(r.factors, bodies);
    in.arrayOf(r.forces, muscles);
    in.arrayOf(r.margins, shells);
    std::vector<uint64_t> inWall;
    in.arrayOf(inWall, shells);
    r.inWall.assign(inWall.begin(), inWall.end());
    in.arrayOf(r.tilts, shells);
    in.arrayOf(r.apexes, shells);
    in.arrayOf(r.widths, shells);
  }
  if (!in.done()) throw sim::StateError("checkpoint state: bytes left over after the body records");
  rows_ = std::move(rows);
}

void BodyTrack::record(const sim::Simulation& simulation) {
  if (params_.bodies.empty() && params_.emitters.empty()) return;
  const sim::ParticleSet& p = simulation.particles();
  const size_t bodies = params_.bodies.size();
  std::vector<Eigen::Vector3d> centre(bodies, Eigen::Vector3d::Zero());
  std::vector<double> count(bodies, 0.0), mass(bodies, 0.0), factor(bodies, 0.0);
  std::vector<float> fluidZ;
  for (size_t i = 0; i < p.size(); ++i) {
    if (p.kind[i] == 0) {
      fluidZ.push_back(p.z[i]);
      continue;
    }
    const size_t b = size_t(p.kind[i] - 1);
    centre[b] += double(p.mass[i]) * Eigen::Vector3d(p.x[i], p.y[i], p.z[i]);
    mass[b] += double(p.mass[i]);
    count[b] += 1.0;
    factor[b] += p.restDensity[i] / simulation.bodies()->initialRestDensity(p.id[i]);
  }
  Row row;
  row.time = simulation.time();
  // The free surface: the 98th percentile of the fluid particles' heights.
  if (!fluidZ.empty()) {
    const size_t k = size_t(0.98 * double(fluidZ.size() - 1));
    std::nth_element(fluidZ.begin(), fluidZ.begin() + long(k), fluidZ.end());
    row.surface = fluidZ[k];
  }
  if (!params_.emitters.empty()) {
    row.level = waterLevel(params_, p);
    row.displaced = bodiesDisplacement(params_, p, row.level);
  }
  for (size_t i = 0; i < p.size(); ++i)
    if (p.kind[i] != 0) row.volume += double(p.mass[i]) / double(p.restDensity[i]);
  for (size_t b = 0; b < bodies; ++b) {
    row.centres.push_back(mass[b] > 0 ? Eigen::Vector3d(centre[b] / mass[b]) : Eigen::Vector3d::Zero());
    row.factors.push_back(count[b] > 0 ? factor[b] / count[b] : 1.0);
    if (walls_[b]) {
      row.margins.push_back(walls_[b]->marginRadius(p));
      row.tilts.push_back(walls_[b]->tiltDegrees(p));
      row.inWall.push_back(walls_[b]->fluidInsideWall(p));
      row.apexes.push_back(walls_[b]->apexHeight(p));
      row.widths.push_back(walls_[b]->shape(p).diameter);
    }
  }
  // The force as applied in the last step (a depth reflex scales the curve's).
  size_t muscle = 0;
  for (const sim::BodyParams& b : params_.bodies)
    for (size_t m = 0; m < b.muscles.size(); ++m, ++muscle)
      row.forces.push_back(simulation.time() > 0.0 ? simulation.bodies()->appliedMuscleForce(muscle)
                                                   : b.muscles[m].force.at(row.time));
  rows_.push_back(std::move(row));
}

nlohmann::json BodyTrack::shellSummary(size_t body) const {
  if (rows_.empty() || body >= walls_.size() || !walls_[body]) return nullptr;
  size_t k = 0;
  for (size_t b = 0; b < body; ++b) k += walls_[b].has_value();
  double smallest = rows_.front().margins[k];
  size_t most = 0;
  double mostAt = 0.0;
  for (const Row& r : rows_) {
    smallest = std::min(smallest, r.margins[k]);
    if (r.inWall[k] > most) {
      most = r.inWall[k];
      mostAt = r.time;
    }
  }
  nlohmann::json summary = {{"margin_radius_at_rest_m", rows_.front().margins[k]},
                            {"margin_radius_min_m", smallest},
                            {"fluid_inside_wall_max", most},
                            {"fluid_inside_wall_max_at_s", mostAt},
                            {"diameter_at_rest_m", rows_.front().widths[k]},
                            {"apex_height_at_rest_m", rows_.front().apexes[k]}};
  if (nlohmann::json swim = swimSummary(body, k); !swim.is_null()) summary["swim"] = std::move(swim);
  return summary;
}

nlohmann::json BodyTrack::pourSummary(const sim::Simulation& simulation) const {
  const std::vector<sim::Emitter>& emitters = simulation.emitters();
  if (emitters.empty() || rows_.empty()) return nullptr;
  // The last row at or before t (the first row when none).
  auto rowBefore = [&](double t) {
    auto it = std::upper_bound(rows_.begin(), rows_.end(), t + 1e-9, [](double v, const Row& r) { return v < r.time; });
    return it == rows_.begin() ? rows_.begin() : std::prev(it);
  };
  // The level's mean over the rows in (t - w, t] (waves and a swimming body's breathing move a
  // single frame's): w is kLevelWindow, or with a pulsed muscle whole periods of its pulses, at
  // least kLevelWindow, and none before the pulses start (a body at rest displaces otherwise than a
  // pulsing one, and the start's transient is over by then) where a whole period fits after it.
  constexpr double kLevelWindow = 3.0;  // s
  double period = 0.0, pulsesFrom = 0.0;
  for (const sim::BodyParams& b : params_.bodies)
    for (const sim::MuscleParams& m : b.muscles)
      if (m.force.type == sim::CurveType::Pulse && m.force.period > 0.0f && period == 0.0) {
        period = m.force.period;
        pulsesFrom = m.force.start;
      }
  auto window = [&](double t) {
    if (!(period > 0.0)) return kLevelWindow;
    const double whole = period * std::ceil(kLevelWindow / period - 1e-9);
    const double fit = std::floor((t - pulsesFrom) / period + 1e-9);
    return t - whole >= pulsesFrom - 1e-9 || fit < 1.0 ? whole : fit * period;
  };
  struct Mean {
    double level, water, volume, from, to;  // the means of the level, of level - displaced and of the bodies'
                                            // own volume; the first and last rows' times
  };
  auto meanLevel = [&](double t) {
    const double w = window(t);
    double sum = 0.0, water = 0.0, volume = 0.0;
    int count = 0;
    auto it = rowBefore(t);
    const double to = it->time;
    double from = to;
    for (; it->time > t - w + 1e-9; --it) {
      sum += it->level;
      water += it->level - it->displaced;
      volume += it->volume;
      ++count;
      from = it->time;
      if (it == rows_.begin()) break;
    }
    const Row& only = *rowBefore(t);
    return count > 0 ? Mean{sum / count, water / count, volume / count, from, to}
                     : Mean{only.level, only.level - only.displaced, only.volume, to, to};
  };
  const double last = rows_.back().time;
  const sim::ContainerParams& box = params_.container;
  const double floorArea = double(box.max.x() - box.min.x()) * double(box.max.y() - box.min.y());
  const double particleVolume = double(simulation.fluidParticleMass()) / double(params_.fluid.restDensity);
  nlohmann::json pours = nlohmann::json::array();
  for (size_t e = 0; e < emitters.size(); ++e) {
    const sim::EmitterParams& q = params_.emitters[e];
    const double start = q.start, end = std::min(double(q.end), last);
    // Settled: the last row before the next pour that starts after this one ends, or the run's end.
    double settled = last;
    for (const sim::EmitterParams& o : params_.emitters)
      if (o.start >= q.end && o.start < settled + 1e-9) settled = std::max(double(o.start) - 1e-6, end);
    const double nozzle = std::numbers::pi * double(q.radius) * double(q.radius) * double(q.speed) * std::max(end - start, 0.0);
    const double emitted = double(emitters[e].spawned()) * particleVolume;
    const Row& before = *rowBefore(start);
    const Row& after = *rowBefore(settled);
    const Mean levelBefore = meanLevel(start), levelSettled = meanLevel(settled);
    const double rise = levelSettled.level - levelBefore.level, expected = emitted / floorArea;
    const double waterRise = levelSettled.water - levelBefore.water;
    nlohmann::json pour = {{"start_s", start},
                           {"end_s", end},
                           {"particles", emitters[e].spawned()},
                           {"blocked_positions", emitters[e].blocked()},
                           {"nozzle_volume_m3", nozzle},
                           {"emitted_volume_m3", emitted},
                           {"emitted_over_nozzle", nozzle > 0.0 ? emitted / nozzle : 0.0},
                           {"level_before_m", levelBefore.level},
                           {"level_before_rows_s", {levelBefore.from, levelBefore.to}},
                           {"level_settled_m", levelSettled.level},
                           {"level_settled_rows_s", {levelSettled.from, levelSettled.to}},
                           {"settled_at_s", after.time},
                           {"level_rise_m", rise},
                           {"expected_rise_m", expected},
                           {"rise_over_expected", expected > 0.0 ? rise / expected : 0.0},
                           {"bodies_displacement_before_m", levelBefore.level - levelBefore.water},
                           {"bodies_displacement_settled_m", levelSettled.level - levelSettled.water},
                           {"bodies_volume_before_m3", levelBefore.volume},
                           {"bodies_volume_settled_m3", levelSettled.volume},
                           {"water_rise_m", waterRise},
                           {"water_rise_over_expected", expected > 0.0 ? waterRise / expected : 0.0}};
    const Row& to = *rowBefore(end);
    nlohmann::json drifts = nlohmann::json::array();
    for (size_t b = 0; b < params_.bodies.size(); ++b) {
      if (params_.bodies[b].shape != sim::BodyShape::Shell) continue;
      const Eigen::Vector2d drift = (to.centres[b] - before.centres[b]).head<2>();
      const Eigen::Vector2d away = (before.centres[b] - q.position.cast<double>()).head<2>();
      drifts.push_back({{"body", params_.bodies[b].name},
                        {"drift_x_m", drift.x()},
                        {"drift_y_m", drift.y()},
                        {"away_from_nozzle", drift.dot(away) > 0.0}});
    }
    if (!drifts.empty()) pour["drift"] = std::move(drifts);
    pours.push_back(std::move(pour));
  }
  return {{"pours", pours},
          {"floor_area_m2", floorArea},
          {"particle_volume_m3", particleVolume},
          {"note", "per emitter: its particles' volume at rest density against nozzle area x speed x open time; the "
                   "water's level (the free surface of the colour field over the whole floor), its mean over a window of whole "
                   "pulse periods (at least 3 s; none before the pulses start) before the pour's start and before the last "
                   "frame before the next pour (or the run's end), against the emitted volume over the floor area; the same of "
                   "the water's own level (the level less the water missing near the bodies, which a bell's pulses move) and "
                   "the bodies' own volume (sum of m / rho0_i); "
                   "each shell's horizontal drift over the pour"}};
}

nlohmann::json BodyTrack::swimSummary(size_t body, size_t k) const {
  const sim::ForceCurve* pulse = nullptr;
  for (const sim::MuscleParams& m : params_.bodies[body].muscles)
    if (m.force.type == sim::CurveType::Pulse && !pulse) pulse = &m.force;
  if (!pulse || !(pulse->period > 0.0f)) return nullptr;
  auto rowAt = [&](double t) {
    return std::min_element(rows_.begin(), rows_.end(), [&](const Row& a, const Row& b) {
      return std::abs(a.time - t) < std::abs(b.time - t);
    });
  };
  const double start = pulse->start, last = rows_.back().time;
  int pulses = 0;
  while (pulses < 10 && start + (pulses + 1) * double(pulse->period) <= last + 1e-9 &&
         start + pulses * double(pulse->period) < double(pulse->end))
    ++pulses;
  if (pulses == 0) return nullptr;
  const double rise = rowAt(start + pulses * double(pulse->period))->apexes[k] - rowAt(start)->apexes[k];
  const double diameter = rows_.front().widths[k];
  return {{"pulses", pulses},
          {"apex_rise_m", rise},
          {"bell_diameters_per_pulse", diameter > 0.0 ? rise / pulses / diameter : 0.0},
          {"note", "net rise of the bell's apex from the first pulse's start over the first pulses (at most 10), "
                   "per pulse, in bell diameters at rest"}};
}

void BodyTrack::write(const fs::path& outDir) const {
  std::ostringstream csv;
  csv << "time_s,fluid_surface_z_m";
  const bool levels = !params_.emitters.empty();
  if (levels) csv << ",water_level_m,bodies_displacement_m,bodies_volume_m3";
  for (const sim::BodyParams& b : params_.bodies)
    csv << "," << b.name << "_x_m," << b.name << "_y_m," << b.name << "_z_m," << b.name << "_depth_m," << b.name
        << "_rest_density_factor";
  for (const sim::BodyParams& b : params_.bodies)
    for (const sim::MuscleParams& m : b.muscles) csv << "," << b.name << "_" << m.name << "_force_N";
  for (const sim::BodyParams& b : params_.bodies)
    if (b.shape == sim::BodyShape::Shell)
      csv << "," << b.name << "_margin_radius_m," << b.name << "_fluid_in_wall," << b.name << "_tilt_deg," << b.name
          << "_apex_z_m," << b.name << "_diameter_m";
  csv << "\n";
  for (const Row& r : rows_) {
    csv << r.time << "," << r.surface;
    if (levels) csv << "," << r.level << "," << r.displaced << "," << r.volume;
    for (size_t b = 0; b < r.centres.size(); ++b)
      csv << "," << r.centres[b].x() << "," << r.centres[b].y() << "," << r.centres[b].z() << ","
          << r.surface - r.centres[b].z() << "," << r.factors[b];
    for (double f : r.forces) csv << "," << f;
    for (size_t k = 0; k < r.margins.size(); ++k)
      csv << "," << r.margins[k] << "," << r.inWall[k] << "," << r.tilts[k] << "," << r.apexes[k] << "," << r.widths[k];
    csv << "\n";
  }
  writeTextAtomic(outDir / "bodies.csv", csv.str());
  if (!rows_.empty() && !rows_.front().forces.empty()) writePlot(outDir / "bodies.png");
}

void BodyTrack::writePlot(const fs::path& file) const {
  Plot plot;
  plot.title = sceneName_ + ": muscle force and body depth";
  plot.x.label = "time (s)";
  plot.y.label = "depth below the surface (m)";
  plot.y2.label = "force per spring (N)";
  for (size_t b = 0; b < params_.bodies.size(); ++b) {
    PlotSeries depth;
    depth.label = params_.bodies[b].name + " depth";
    for (const Row& r : rows_) {
      depth.x.push_back(r.time);
      depth.y.push_back(r.surface - r.centres[b].z());
    }
    plot.series.push_back(std::move(depth));
  }
  size_t m = 0;
  for (const sim::BodyParams& b : params_.bodies)
    for (const sim::MuscleParams& muscle : b.muscles) {
      PlotSeries force;
      force.label = b.name + " " + muscle.name + " force";
      force.axis = 1;
      for (const Row& r : rows_) {
        force.x.push_back(r.time);
        force.y.push_back(r.forces[m]);
      }
      plot.series.push_back(std::move(force));
      ++m;
    }
  pipeline::writePlot(plot, file);
}

}  // namespace kurage::pipeline
