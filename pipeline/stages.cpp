#include "pipeline/stages.h"

#include "pipeline/interrupt.h"
#include "pipeline/io/checkpoint.h"
#include "pipeline/exports.h"
#include "pipeline/io/exr.h"
#include "pipeline/io/files.h"
#include "pipeline/io/image_file.h"
#include "pipeline/io/stamp.h"
#include "pipeline/io/surface_file.h"
#include "pipeline/io/video.h"
#include "pipeline/analysis/shell_wall.h"
#include "pipeline/io/particle_cache.h"
#include "pipeline/progress.h"
#include "pipeline/render_scene.h"
#include "pipeline/sim_frame.h"
#include "pipeline/io/plot.h"
#include "render/tracer.h"
#include "sim/simulation.h"

#include <Eigen/Core>
#include <nlohmann/json.hpp>
#include <png.h>
#include <tbb/version.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <iostream>
#include <optional>
#include <sstream>
#include <stdexcept>

namespace kurage::pipeline {

namespace fs = std::filesystem;

namespace {

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

void requireFile(const fs::path& file, const char* producer) {
  if (!fs::exists(file))
    throw std::runtime_error(file.string() + ": missing; run `kurage " + producer + "` for these frames first");
}

// Per frame: each body's centre of mass and mean stretch, each muscle's force, the fluid's surface
// height; written as OUT/bodies.csv (and plotted when the scene has muscles).
class BodyTrack {
public:
  explicit BodyTrack(const Scene& scene) : scene_(scene) {}

  // The shells as built: call with the simulation at t = 0, before any record.
  void start(const sim::Simulation& simulation) {
    const sim::ParticleSet& p = simulation.particles();
    walls_.clear();
    for (size_t b = 0; b < scene_.sim.bodies.size(); ++b)
      walls_.push_back(scene_.sim.bodies[b].shape == sim::BodyShape::Shell
                           ? std::optional<ShellWall>(std::in_place, scene_.sim.bodies[b], int(b + 1), p,
                                                      scene_.sim.fluid.spacing)
                           : std::nullopt);
  }

  // The rows so far, for checkpoints (pipeline/io/checkpoint.h).
  std::string saveState() const {
    sim::StateWriter out;
    out.value(uint64_t(rows_.size()));
    for (const Row& r : rows_) {
      out.value(r.time);
      out.value(r.surface);
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

  // Throws sim::StateError for rows that do not fit the scene.
  void restoreState(const std::string& bytes) {
    sim::StateReader in(bytes);
    const uint64_t count = in.value<uint64_t>();
    if (count > uint64_t(scene_.output.frameCount()))
      throw sim::StateError("checkpoint state: more body records than frames");
    const size_t bodies = scene_.sim.bodies.size();
    size_t muscles = 0, shells = 0;
    for (const sim::BodyParams& b : scene_.sim.bodies) {
      muscles += b.muscles.size();
      shells += b.shape == sim::BodyShape::Shell;
    }
    std::vector<Row> rows(static_cast<size_t>(count));
    for (Row& r : rows) {
      r.time = in.value<double>();
      r.surface = in.value<double>();
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

  void record(const sim::Simulation& simulation) {
    if (scene_.sim.bodies.empty()) return;
    const sim::ParticleSet& p = simulation.particles();
    const size_t bodies = scene_.sim.bodies.size();
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
    for (const sim::BodyParams& b : scene_.sim.bodies)
      for (size_t m = 0; m < b.muscles.size(); ++m, ++muscle)
        row.forces.push_back(simulation.time() > 0.0 ? simulation.bodies()->appliedMuscleForce(muscle)
                                                     : b.muscles[m].force.at(row.time));
    rows_.push_back(std::move(row));
  }

  // Per shell body, for run.json: the margin radius at rest (t = 0) and its smallest value, and
  // the most fluid particles found inside the wall in a frame (ShellWall::fluidInsideWall).
  nlohmann::json shellSummary(size_t body) const {
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

  // The swimming speed of a shell with a pulsed muscle (its first), in bell diameters per pulse:
  // the net rise of its apex from the first pulse's start to the end of its tenth period (or of
  // the last whole period recorded), over the pulses, over the diameter at rest.
  nlohmann::json swimSummary(size_t body, size_t k) const {
    const sim::ForceCurve* pulse = nullptr;
    for (const sim::MuscleParams& m : scene_.sim.bodies[body].muscles)
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

  void write(const fs::path& outDir) const {
    std::ostringstream csv;
    csv << "time_s,fluid_surface_z_m";
    for (const sim::BodyParams& b : scene_.sim.bodies)
      csv << "," << b.name << "_x_m," << b.name << "_y_m," << b.name << "_z_m," << b.name << "_depth_m," << b.name
          << "_rest_density_factor";
    for (const sim::BodyParams& b : scene_.sim.bodies)
      for (const sim::MuscleParams& m : b.muscles) csv << "," << b.name << "_" << m.name << "_force_N";
    for (const sim::BodyParams& b : scene_.sim.bodies)
      if (b.shape == sim::BodyShape::Shell)
        csv << "," << b.name << "_margin_radius_m," << b.name << "_fluid_in_wall," << b.name << "_tilt_deg," << b.name
            << "_apex_z_m," << b.name << "_diameter_m";
    csv << "\n";
    for (const Row& r : rows_) {
      csv << r.time << "," << r.surface;
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

  // The paper's Fig. 3: the muscles' force against time, with each body's measured depth below
  // the free surface added.
  void writePlot(const fs::path& file) const {
    Plot plot;
    plot.title = scene_.name + ": muscle force and body depth";
    plot.x.label = "time (s)";
    plot.y.label = "depth below the surface (m)";
    plot.y2.label = "force per spring (N)";
    for (size_t b = 0; b < scene_.sim.bodies.size(); ++b) {
      PlotSeries depth;
      depth.label = scene_.sim.bodies[b].name + " depth";
      for (const Row& r : rows_) {
        depth.x.push_back(r.time);
        depth.y.push_back(r.surface - r.centres[b].z());
      }
      plot.series.push_back(std::move(depth));
    }
    size_t m = 0;
    for (const sim::BodyParams& b : scene_.sim.bodies)
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

private:
  struct Row {
    double time = 0.0;
    double surface = 0.0;
    std::vector<Eigen::Vector3d> centres;
    std::vector<double> factors;
    std::vector<double> forces;
    std::vector<double> margins;  // per shell body: margin radius (m)
    std::vector<size_t> inWall;   // per shell body: fluid particles inside its wall
    std::vector<double> tilts;    // per shell body: tilt from its axis as built (degrees)
    std::vector<double> apexes;   // per shell body: height of its highest particle (m)
    std::vector<double> widths;   // per shell body: its diameter (ShellWall::shape, m)
  };
  const Scene& scene_;
  std::vector<std::optional<ShellWall>> walls_;  // per body; shells only
  std::vector<Row> rows_;
};

}  // namespace

std::string stageHash(const Scene& scene, const std::string& stage) {
  nlohmann::json all = sceneToJson(scene);
  nlohmann::json inputs = all;
  for (const char* key : {"name", "description", "surface", "render", "preview_quality", "output"}) inputs.erase(key);
  inputs["output_fps"] = all["output"]["fps"];  // frame f is at f / fps; the duration changes no frame
  if (stage == "sim") return hex64(fnv1a64(inputs.dump()));
  inputs["surface"] = all["surface"];
  if (stage == "surface") return hex64(fnv1a64(inputs.dump()));
  inputs["render"] = all["render"];
  if (stage == "render") return hex64(fnv1a64(inputs.dump()));
  throw std::invalid_argument("stageHash: unknown stage " + stage);
}

std::pair<int, int> frameRange(const Scene& scene, const StageOptions& options) {
  const int count = scene.output.frameCount();
  const int last = options.lastFrame < 0 ? count - 1 : options.lastFrame;
  if (options.firstFrame < 0 || options.firstFrame > last || last >= count)
    throw std::invalid_argument("--frames " + std::to_string(options.firstFrame) + "-" + std::to_string(last) +
                                ": the scene has frames 0-" + std::to_string(count - 1));
  return {options.firstFrame, last};
}

nlohmann::json versionInfo() {
  return {{"kurage", KURAGE_VERSION},
          {"openvdb", render::openvdbVersion()},
          {"embree", render::embreeVersion()},
          {"tbb", TBB_VERSION_STRING},
          {"eigen", std::to_string(EIGEN_WORLD_VERSION) + "." + std::to_string(EIGEN_MAJOR_VERSION) + "." +
                        std::to_string(EIGEN_MINOR_VERSION)},
          {"libpng", PNG_LIBPNG_VER_STRING},
          {"nlohmann_json", std::to_string(NLOHMANN_JSON_VERSION_MAJOR) + "." +
                                std::to_string(NLOHMANN_JSON_VERSION_MINOR) + "." +
                                std::to_string(NLOHMANN_JSON_VERSION_PATCH)}};
}

RunRecord::RunRecord(const fs::path& outDir, const Scene& scene, const std::string& sceneFile, const std::string& task)
    : path_(task.empty() ? outDir / "run.json" : outDir / "records" / (task + ".json")) {
  if (!task.empty()) fs::create_directories(path_.parent_path());
  if (fs::exists(path_)) {
    try {
      data_ = nlohmann::json::parse(readText(path_));
    } catch (const std::exception&) {
      data_ = nlohmann::json::object();  // an unreadable record is replaced, not trusted
    }
  }
  if (!data_.is_object()) data_ = nlohmann::json::object();
  data_["scene_file"] = sceneFile;
  data_["versions"] = versionInfo();
  data_["parameters"] = sceneToJson(scene);
  if (!data_.contains("stages")) data_["stages"] = nlohmann::json::object();
}

void RunRecord::setStage(const std::string& name, nlohmann::json stage) { data_["stages"][name] = std::move(stage); }

void RunRecord::save() const { writeTextAtomic(path_, data_.dump(2) + "\n"); }

namespace {

// --resume: restores the simulation and the body records from OUT/checkpoint.bin and returns the
// frame it holds, or -1 (start at t = 0, saying why) when there is none, it lies past the frames
// asked for, or a cache it covers is missing or damaged. A damaged checkpoint, or one of other
// scene parameters or another kurage, is an error naming the file.
int resumeSimulation(const Scene& scene, const StageOptions& options, const std::string& simHash,
                     sim::Simulation& simulation, BodyTrack& track) {
  const fs::path file = checkpointFile(options.outDir);
  if (!fs::exists(file)) {
    std::printf("sim: no checkpoint %s: starting at t = 0\n", file.string().c_str());
    return -1;
  }
  const Checkpoint c = readCheckpoint(file, simHash);
  const auto [first, last] = frameRange(scene, options);
  if (c.frame < 0 || c.frame > last) {
    std::printf("sim: the checkpoint holds frame %d, outside the frames 0-%d: starting at t = 0\n", c.frame, last);
    return -1;
  }
  const StageContext context(scene, options.outDir);
  const StageSpec& sim = findStage("sim");
  for (int f = first; f <= c.frame; ++f)
    if (!sim.upToDate(context, f)) {
      std::printf("sim: the cache of frame %d is missing or damaged: starting at t = 0\n", f);
      return -1;
    }
  try {
    sim::StateReader reader(c.simState);
    simulation.restoreState(reader);
    track.restoreState(c.stageState);
  } catch (const sim::StateError& e) {
    throw IoError(file.string() + ": " + e.what());
  }
  if (simulation.time() != c.time) throw IoError(file.string() + ": its state's time disagrees with its header");
  std::printf("sim: resuming after frame %d (t = %g s) from %s\n", c.frame, c.time, file.string().c_str());
  return c.frame;
}

}  // namespace

void runSimStage(const Scene& scene, const StageOptions& options, RunRecord& record) {
  const auto [first, last] = frameRange(scene, options);
  const auto start = std::chrono::steady_clock::now();
  const fs::path folder = options.outDir / "particles";
  fs::create_directories(folder);
  const std::string simHash = stageHash(scene, "sim");
  sim::Simulation simulation(scene.sim);
  BodyTrack track(scene);
  track.start(simulation);
  const fs::path checkpoint = checkpointFile(options.outDir);
  const int resumed = options.resume ? resumeSimulation(scene, options, simHash, simulation, track) : -1;
  int saved = resumed;  // the frame of the newest checkpoint
  const auto save = [&](int f) {
    sim::StateWriter state;
    simulation.saveState(state);
    writeCheckpoint(checkpoint, {f, simulation.time(), state.take(), track.saveState()}, simHash);
    saved = f;
  };
  Progress progress("sim", last + 1, options.progress);
  for (int f = resumed + 1; f <= last; ++f) {
    if (interruptPending()) {
      if (f - 1 > saved) save(f - 1);  // a resume starts after the last frame done
      throwIfInterrupted();
    }
    simulation.advanceTo(scene.output.frameTime(f));
    track.record(simulation);
    if (f >= first) {
      ParticleFrame frame = frameFromSimulation(scene, simulation, f);
      frame.sceneHash = simHash;
      writeParticleFrame(frameFile(folder, f, "vdb"), frame);
    }
    if (f == last || (options.checkpointEvery > 0 && (f + 1) % options.checkpointEvery == 0)) save(f);
    progress.advance(f + 1);
  }
  progress.finish();
  if (!scene.sim.bodies.empty()) track.write(options.outDir);

  const sim::SimStats& stats = simulation.stats();
  nlohmann::json bounds = nlohmann::json::object();
  for (size_t b = 0; b < size_t(sim::StepBound::Count); ++b)
    if (stats.boundCounts[b]) bounds[std::string(sim::stepBoundName(sim::StepBound(b)))] = stats.boundCounts[b];
  nlohmann::json stageTimes = nlohmann::json::object();
  nlohmann::json stagesRun = nlohmann::json::array();
  double stepSeconds = 0.0;
  for (size_t s = 0; s < size_t(sim::Stage::Count); ++s) stepSeconds += stats.stageSeconds[s];
  for (size_t s = 0; s < size_t(sim::Stage::Count); ++s)
    if (stats.stageRan(sim::Stage(s))) {
      const std::string name(sim::stageName(sim::Stage(s)));
      stagesRun.push_back(name);
      stageTimes[name] = {{"seconds", stats.stageSeconds[s]},
                          {"share", stepSeconds > 0.0 ? stats.stageSeconds[s] / stepSeconds : 0.0},
                          {"calls", stats.stageCalls[s]}};
    }
  const sim::SolverStats& ss = simulation.solver().stats();
  const double solverSteps = std::max<double>(1.0, double(ss.steps));
  nlohmann::json solver = {
      {"name", scene.sim.fluid.solver},
      {"mean_density_error", stats.steps ? stats.densityErrorSum / double(stats.steps) : 0.0},
      {"max_density_error", stats.densityErrorMax},
      {"density_error_note", "compression measured by each step's density pass: mean over fluid particles of "
                             "max(rho - rho0, 0) / rho0; the run's mean and largest (fractions)"}};
  if (!simulation.solver().pressureInForces()) {
    solver["density_solve"] = {{"mean_iterations", double(ss.densityIterations) / solverSteps},
                               {"max_iterations", ss.maxDensityIterations},
                               {"cap", scene.sim.fluid.maxIterations},
                               {"cap_hits", ss.densityCapHits},
                               {"final_error", ss.lastDensityError},
                               {"mean_final_error", ss.sumDensityError / solverSteps},
                               {"max_final_error", ss.maxDensityError},
                               {"tolerance", 0.01 * scene.sim.fluid.maxDensityError}};
    solver["divergence_solve"] = {{"method", scene.sim.fluid.divergenceSolve == sim::DivergenceSolve::Jacobi ? "jacobi" : "cg"},
                                  {"mean_iterations", double(ss.divergenceIterations) / solverSteps},
                                  {"max_iterations", ss.maxDivergenceIterations},
                                  {"cap", scene.sim.fluid.maxDivergenceIterations},
                                  {"cap_hits", ss.divergenceCapHits},
                                  {"final_error", ss.lastDivergenceError},
                                  {"tolerance", 0.01 * scene.sim.fluid.maxDivergenceError}};
    solver["torn_body_particles"] = {
        {"steps", ss.tornSteps},
        {"max_at_once", ss.maxTorn},
        {"note", "telescopic body particles stretched until their rest density fell below a quarter of its "
                 "initial value, left out of the solves' unknowns (docs/PHYSICS.md, Bodies under DFSPH)"}};
    if (ss.tornSteps)
      std::cerr << "kurage: warning: in " << ss.tornSteps << " of " << ss.steps << " steps (up to " << ss.maxTorn
                << " at once) telescopic body particles were stretched below a quarter of their rest density and "
                   "left out of the " << scene.sim.fluid.solver << " solver's unknowns; see run.json "
                   "stages.sim.solver.torn_body_particles\n";
    if (ss.densityCapHits || ss.divergenceCapHits)
      std::cerr << "kurage: warning: the " << scene.sim.fluid.solver << " solver stopped at its iteration cap in "
                << ss.densityCapHits << " density and " << ss.divergenceCapHits << " divergence solves of "
                << ss.steps << " steps (fluid.max_iterations " << scene.sim.fluid.maxIterations
                << ", fluid.max_divergence_iterations " << scene.sim.fluid.maxDivergenceIterations
                << "): the density error there is above the tolerance; see run.json stages.sim.solver\n";
  }
  if (const sim::BoundaryParticles* bp = simulation.boundaryParticles()) solver["boundary_particles"] = bp->size();
  // fluid.kernel as run ("auto" resolved)
  solver["kernel"] = simulation.params().fluid.kernel == sim::SphKernel::CubicSpline ? "cubic_spline" : "mueller2003";
  const sim::StepLimit stability = simulation.stabilityLimit();
  record.data()["derived"] = {
      {"fluid_particle_mass_kg", simulation.fluidParticleMass()},
      {"fluid_particle_mass_note", "calibrated so that a particle deep inside the initial lattice has density rho0"},
      {"support_radius_m", scene.sim.fluid.supportRadiusMetres()},
      {"speed_of_sound_m_per_s", simulation.solver().incompressible() ? 0.0 : scene.sim.fluid.speedOfSound()},
      {"stability_bound_at_rest_s", stability.step},
      {"stability_bound_at_rest_active", sim::stepBoundName(stability.bound)},
      {"frame_count", scene.output.frameCount()}};
  record.setStage("sim", {{"seconds", secondsSince(start)},
                          {"frames", {first, last}},
                          {"resumed_after_frame", resumed >= 0 ? nlohmann::json(resumed) : nlohmann::json(nullptr)},
                          {"checkpoint", {{"file", checkpoint.filename().string()}, {"frame", saved},
                                          {"every_frames", options.checkpointEvery}}},
                          {"particles", simulation.particles().size()},
                          {"emitted_particles", stats.emitted},
                          {"emitter_blocked_positions", stats.emitterBlocked},
                          {"removed_by_sinks", stats.removed},
                          {"steps", stats.steps},
                          {"min_step_s", stats.minStep},
                          {"max_step_s", stats.maxStep},
                          {"active_bound_counts", bounds},
                          {"stages_run", stagesRun},
                          {"step_stages", stageTimes},
                          {"solver", solver}});
  if (const sim::BodySystem* bodies = simulation.bodies()) {
    nlohmann::json list = nlohmann::json::array();
    for (size_t b = 0; b < scene.sim.bodies.size(); ++b)
    {
      list.push_back({{"name", scene.sim.bodies[b].name},
                      {"kind", b + 1},
                      {"particle_mass_kg", bodies->particleMass(b)},
                      {"rest_density_kg_per_m3", bodies->restDensity(b)},
                      {"mean_specific_gravity", bodies->meanSpecificGravity(b)}});
      if (nlohmann::json shell = track.shellSummary(b); !shell.is_null()) list.back()["shell"] = std::move(shell);
    }
    const sim::BodyStats& bs = bodies->stats();
    record.data()["stages"]["sim"]["bodies"] = {
        {"bodies", list},
        {"body_particles", bodies->particleCount()},
        {"springs", bodies->springCount()},
        {"spring_step_bound_s", bodies->springStep() * scene.sim.timeStep.springFactor},
        {"collision_cap", scene.sim.collisions.maxPasses},
        {"collision_cap_hits", bs.capHits},
        {"collision_passes", bs.collisionPasses},
        {"collisions_resolved", bs.collisionsResolved},
        {"most_collision_passes_in_a_step", bs.mostPasses}};
  }
  record.save();
}

std::map<std::string, render::LevelSet> surfaceParticles(const Scene& scene, const fs::path& particleFile) {
  return surfaceFrame(scene, readParticleFrame(particleFile));
}

std::map<std::string, render::LevelSet> surfaceFrame(const Scene& scene, const ParticleFrame& frame) {
  // Kind 0 is the fluid, kind b + 1 the body b; chains are drawn as curves, not surfaces.
  std::vector<std::vector<Eigen::Vector3f>> byKind(scene.sim.bodies.size() + 1);
  for (size_t i = 0; i < frame.size(); ++i) {
    const size_t kind = size_t(frame.kind[i]);
    if (kind < byKind.size()) byKind[kind].emplace_back(frame.px[i], frame.py[i], frame.pz[i]);
  }
  const auto build = [&](const std::vector<Eigen::Vector3f>& positions, const render::MetaballParams& params) {
    render::LevelSet levelSet = render::buildMetaballLevelSet(positions, params);
    if (scene.surface.clipToContainer) {
      const Eigen::Vector3f margin = Eigen::Vector3f::Constant(0.25f * params.voxelSize);
      render::intersectWithBox(levelSet, scene.sim.container.min - margin, scene.sim.container.max + margin);
    }
    return levelSet;
  };
  std::map<std::string, render::LevelSet> surfaces;
  surfaces.emplace("fluid", build(byKind[0], scene.surface.fluid));
  for (size_t b = 0; b < scene.sim.bodies.size(); ++b)
    if (scene.sim.bodies[b].shape != sim::BodyShape::Chain)
      surfaces.emplace(scene.sim.bodies[b].name, build(byKind[b + 1], scene.surface.bodies));
  return surfaces;
}

namespace {

fs::path cacheFile(const fs::path& outDir, int f) { return frameFile(outDir / "particles", f, "vdb"); }
fs::path surfaceFile(const fs::path& outDir, int f) { return frameFile(outDir / "surfaces", f, "vdb"); }

void surfaceOneFrame(const StageContext& c, int f, FrameTally& tally) {
  const std::map<std::string, render::LevelSet> surfaces =
      surfaceFrame(c.scene, readParticleFrame(cacheFile(c.outDir, f), c.stamp("sim", f)));
  std::map<std::string, const render::LevelSet*> grids;
  for (const auto& [name, grid] : surfaces) {
    grids[name] = &grid;
    tally["voxels"] += double(grid.activeVoxelCount());
  }
  writeSurfaceFile(surfaceFile(c.outDir, f), grids, c.scene.output.frameTime(f), f, c.surfaceHash);
}

void summariseSurface(const Scene&, const FrameTally& tally, int framesDone, nlohmann::json& stage) {
  stage["mean_active_voxels"] = framesDone > 0 ? tally.at("voxels") / framesDone : 0.0;
}

}  // namespace

void runSurfaceStage(const Scene& scene, const StageOptions& options, RunRecord& record) {
  runFrameStage(findStage("surface"), scene, options, record);
}

render::Image renderSurfaces(const Scene& scene, const std::map<std::string, render::LevelSet>& surfaces, double time,
                             render::RenderStats* stats, const std::vector<render::CurveSet>& curves,
                             render::FrameLayers* layers) {
  std::vector<render::TriangleMesh> meshes;
  meshes.reserve(surfaces.size());
  render::RenderScene view = makeRenderScene(scene, time);
  const std::vector<std::string> kinds = kindNames(scene);
  for (const auto& [name, levelSet] : surfaces) {
    if (levelSet.empty()) continue;
    meshes.push_back(render::meshLevelSet(levelSet));
    const auto kind = std::find(kinds.begin(), kinds.end(), name);
    view.meshes.push_back({&meshes.back(), name == "fluid" ? scene.render.fluidMaterial : scene.render.bodyMaterial,
                           objectIdOfKind(kind == kinds.end() ? 0 : int(kind - kinds.begin()))});
  }
  view.curves = curves;
  if (layers) layers->objectNames = objectNames(scene);
  return render::renderFrame(view, scene.render.settings, stats, layers);
}

namespace {

std::vector<fs::path> renderOutputs(const StageContext& c, int f) {
  std::vector<fs::path> files;
  if (c.scene.render.outputs.png) files.push_back(frameFile(c.outDir / "frames", f, "png"));
  if (c.scene.render.outputs.exr) files.push_back(frameFile(c.outDir / "frames", f, "exr"));
  return files;
}

bool renderUpToDate(const StageContext& c, int f) {
  const FileStamp stamp = c.stamp("render", f);
  for (const fs::path& file : renderOutputs(c, f))
    if (!(file.extension() == ".png" ? pngStampMatches(file, stamp) : exrStampMatches(file, stamp))) return false;
  return true;
}

void renderOneFrame(const StageContext& c, int f, FrameTally& tally) {
  const Scene& scene = c.scene;
  render::RenderStats stats;
  std::vector<render::CurveSet> curves;
  if (hasChains(scene)) curves.push_back(chainTubes(scene, readParticleFrame(cacheFile(c.outDir, f), c.stamp("sim", f))));
  render::FrameLayers layers;
  const render::Image image =
      renderSurfaces(scene, readSurfaceFile(surfaceFile(c.outDir, f), c.stamp("surface", f)), scene.output.frameTime(f),
                     &stats, curves, scene.render.outputs.exr ? &layers : nullptr);
  tally["primary_rays"] += double(stats.primaryRays);
  tally["total_rays"] += double(stats.totalRays);
  tally["trace_seconds"] += stats.seconds;
  const FileStamp stamp = c.stamp("render", f);
  for (const fs::path& file : renderOutputs(c, f)) {
    if (file.extension() == ".png")
      writePng(image, file, scene.render.settings.transparentBackground, scene.render.bitDepth, &stamp);
    else
      writeExr(file, image, &layers, scene.output.frameTime(f), f, &stamp);
  }
}

void summariseRender(const Scene& scene, const FrameTally& tally, int, nlohmann::json& stage) {
  const auto get = [&tally](const char* key) { return tally.count(key) ? tally.at(key) : 0.0; };
  stage["width"] = scene.render.settings.width;
  stage["height"] = scene.render.settings.height;
  stage["samples"] = scene.render.settings.samplesPerPixel;
  stage["max_depth"] = scene.render.settings.maxDepth;
  stage["outputs"] = nlohmann::json::array();
  if (scene.render.outputs.png) stage["outputs"].push_back("png");
  if (scene.render.outputs.exr) stage["outputs"].push_back("exr");
  stage["primary_rays"] = uint64_t(get("primary_rays"));
  stage["total_rays"] = uint64_t(get("total_rays"));
  stage["trace_seconds"] = get("trace_seconds");
  stage["total_mrays_per_s"] = get("trace_seconds") > 0.0 ? get("total_rays") / get("trace_seconds") * 1e-6 : 0.0;
}

}  // namespace

void runRenderStage(const Scene& scene, const StageOptions& options, RunRecord& record) {
  runFrameStage(findStage("render"), scene, options, record);
}

void runExportStage(const Scene& scene, const StageOptions& options, RunRecord& record) {
  const auto [first, last] = frameRange(scene, options);
  const auto start = std::chrono::steady_clock::now();
  exportFrames(scene, scene.output.exports, options.outDir, first, last);
  record.setStage("export", {{"frames", last - first + 1}, {"seconds", secondsSince(start)}});
  record.save();
}

namespace {

bool always(const Scene&) { return true; }
bool exportsWanted(const Scene& scene) { return scene.output.exports.any(); }

std::vector<fs::path> simOutputs(const StageContext& c, int f) { return {cacheFile(c.outDir, f)}; }
std::vector<fs::path> surfaceOutputs(const StageContext& c, int f) { return {surfaceFile(c.outDir, f)}; }
std::vector<fs::path> noOutputs(const StageContext&, int) { return {}; }

std::vector<StageInput> noInputs(const StageContext&, int) { return {}; }
std::vector<StageInput> surfaceInputs(const StageContext& c, int f) { return {{cacheFile(c.outDir, f), "sim"}}; }
// Chains are not surfaced: their tubes come from the particle caches.
std::vector<StageInput> renderInputs(const StageContext& c, int f) {
  std::vector<StageInput> in{{surfaceFile(c.outDir, f), "surface"}};
  if (hasChains(c.scene)) in.push_back({cacheFile(c.outDir, f), "sim"});
  return in;
}

// True when `read` (a stamped reader: checksum, then stage, hash and frame) accepts the file.
template <class Reader>
bool readsBack(const fs::path& file, Reader read) {
  if (!fs::exists(file)) return false;
  try {
    read(file);
    return true;
  } catch (const std::exception&) {
    return false;
  }
}

bool simUpToDate(const StageContext& c, int f) {
  return readsBack(cacheFile(c.outDir, f), [&](const fs::path& p) { readParticleFrame(p, c.stamp("sim", f)); });
}

bool surfaceUpToDate(const StageContext& c, int f) {
  return readsBack(surfaceFile(c.outDir, f), [&](const fs::path& p) { readSurfaceFile(p, c.stamp("surface", f)); });
}

bool neverUpToDate(const StageContext&, int) { return false; }

}  // namespace

const std::vector<StageSpec>& stageTable() {
  static const std::vector<StageSpec> table{
      {"sim", "particles", "particle caches", true, always, noInputs, simOutputs, simUpToDate, nullptr, nullptr,
       runSimStage},
      {"surface", "surfaces", "surfaces", false, always, surfaceInputs, surfaceOutputs, surfaceUpToDate,
       surfaceOneFrame, summariseSurface, runSurfaceStage},
      {"render", "frames", "frames", false, always, renderInputs, renderOutputs, renderUpToDate, renderOneFrame,
       summariseRender, runRenderStage},
      {"export", "exports", "exports", false, exportsWanted, noInputs, noOutputs, neverUpToDate, nullptr, nullptr,
       runExportStage}};
  return table;
}

const StageSpec& findStage(const std::string& name) {
  for (const StageSpec& s : stageTable())
    if (name == s.name) return s;
  throw std::invalid_argument("unknown stage " + name);
}

StageContext::StageContext(const Scene& s, fs::path out)
    : scene(s), outDir(std::move(out)), simHash(stageHash(s, "sim")), surfaceHash(stageHash(s, "surface")),
      renderHash(stageHash(s, "render")) {}

FileStamp StageContext::stamp(const std::string& stage, int frame) const {
  if (stage == "sim") return {stage, simHash, frame};
  if (stage == "surface") return {stage, surfaceHash, frame};
  if (stage == "render") return {stage, renderHash, frame};
  throw std::invalid_argument("StageContext::stamp: unknown stage " + stage);
}

void runFrameStage(const StageSpec& stage, const Scene& scene, const StageOptions& options, RunRecord& record) {
  const auto [first, last] = frameRange(scene, options);
  const auto start = std::chrono::steady_clock::now();
  const StageContext context(scene, options.outDir);
  // Frames whose outputs are whole and from the same inputs and settings are kept (incremental);
  // --force redoes them. The rest need their inputs.
  std::vector<int> todo;
  for (int f = first; f <= last; ++f)
    if (options.force || !stage.upToDate(context, f)) todo.push_back(f);
  for (int f : todo)
    for (const StageInput& in : stage.inputs(context, f)) requireFile(in.file, in.producer);
  fs::create_directories(options.outDir / stage.folder);
  Progress progress(stage.name, int(todo.size()), options.progress);
  FrameTally tally;
  int done = 0;
  for (int f : todo) {
    throwIfInterrupted();
    stage.perFrame(context, f, tally);
    progress.advance(++done);
  }
  progress.finish();
  nlohmann::json entry = {{"seconds", secondsSince(start)},
                          {"frames", {first, last}},
                          {"frames_done", done},
                          {"frames_skipped", (last - first + 1) - done}};
  stage.summarise(scene, tally, done, entry);
  record.setStage(stage.name, std::move(entry));
  record.save();
}

void encodeSceneVideo(const Scene& scene, const fs::path& outDir, int first, int last, bool force) {
  if (!scene.render.outputs.png) {
    std::printf("video: none (render.outputs.png is false; the video is made from the PNG frames)\n");
    return;
  }
  // The stamp names the frames' bytes as well as the settings: frames rendered again with the
  // same settings (after they were deleted, or by another build of the tracer) remake the movie.
  uint64_t frames = fnv1a64("");
  for (int f = first; f <= last; ++f) {
    const fs::path frame = frameFile(outDir / "frames", f, "png");
    if (fs::exists(frame)) frames = fnv1a64(readFile(frame), frames);
  }
  char stamp[200];
  std::snprintf(stamp, sizeof stamp, "video %s %d %d %g %016llx", stageHash(scene, "render").c_str(), first,
                last - first + 1, scene.output.fps, static_cast<unsigned long long>(frames));
  encodeVideoAndReport(outDir / "frames", first, last - first + 1, scene.output.fps, outDir / (scene.name + ".mp4"),
                       stamp, force);
}

}  // namespace kurage::pipeline
