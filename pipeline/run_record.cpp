#include "pipeline/run_record.h"

#include "pipeline/io/files.h"
#include "pipeline/io/json_file.h"
#include "render/surfacing.h"
#include "render/embree_scene.h"
#include "sim/simulation.h"

#include <Eigen/Core>
#include <png.h>
#include <tbb/version.h>

#include <algorithm>
#include <iostream>
#include <variant>

namespace kurage::pipeline {

namespace fs = std::filesystem;

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
  if (!task.empty()) outputFolder(outDir, "records");
  if (fs::exists(path_)) {
    try {
      data_ = readJson(path_);
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
// The solver's own report (sim::SolverReport) into run.json's `out`, each '.' in a key a nested
// object, and its warnings through `warn(message, key)`.
template <class Warn>
void addSolverReport(nlohmann::json& out, const sim::PressureSolver& solver, const Warn& warn) {
  sim::SolverReport report;
  solver.report(report);
  for (const auto& [key, value] : report.entries) {
    std::string pointer = "/" + key;
    std::replace(pointer.begin(), pointer.end(), '.', '/');
    std::visit([&](const auto& v) { out[nlohmann::json::json_pointer(pointer)] = v; }, value);
  }
  for (const sim::SolverWarning& w : solver.warnings())
    warn(w.message, "stages.sim.solver" + (w.reportKey.empty() ? "" : "." + w.reportKey));
}
}  // namespace

void recordSimStage(RunRecord& record, const Scene& scene, const sim::Simulation& simulation, const BodyTrack& track,
                    const SimStageRun& run) {
  const sim::SimStats& stats = simulation.stats();
  nlohmann::json bounds = nlohmann::json::object();
  for (size_t b = 0; b < size_t(sim::StepBound::Count); ++b)
    if (stats.boundCounts[b]) bounds[std::string(sim::stepBoundName(sim::StepBound(b)))] = stats.boundCounts[b];
  nlohmann::json phaseTimes = nlohmann::json::object();
  nlohmann::json phasesRun = nlohmann::json::array();
  double stepSeconds = 0.0;
  for (size_t s = 0; s < size_t(sim::StepPhase::Count); ++s) stepSeconds += stats.phaseSeconds[s];
  for (size_t s = 0; s < size_t(sim::StepPhase::Count); ++s)
    if (stats.phaseRan(sim::StepPhase(s))) {
      const std::string name(sim::phaseName(sim::StepPhase(s)));
      phasesRun.push_back(name);
      phaseTimes[name] = {{"seconds", stats.phaseSeconds[s]},
                          {"share", stepSeconds > 0.0 ? stats.phaseSeconds[s] / stepSeconds : 0.0},
                          {"calls", stats.phaseCalls[s]}};
    }
  // What the user should know, printed and kept in stages.sim.warnings (the report shows them).
  nlohmann::json warnings = nlohmann::json::array();
  const auto warn = [&warnings](const std::string& message, const std::string& key) {
    std::cerr << "kurage: warning: " << message << "; see run.json " << key << "\n";
    warnings.push_back({{"message", message}, {"key", key}});
  };
  nlohmann::json solver = {
      {"name", scene.sim.fluid.solver.name()},
      {"mean_density_error", stats.steps ? stats.densityErrorSum / double(stats.steps) : 0.0},
      {"max_density_error", stats.densityErrorMax},
      {"density_error_note", "compression measured by each step's density pass: mean over fluid particles of "
                             "max(rho - rho0, 0) / rho0; the run's mean and largest (fractions)"}};
  addSolverReport(solver, simulation.solver(), warn);
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
  record.setStage("sim", {{"seconds", run.seconds},
                          {"frames", {run.first, run.last}},
                          {"resumed_after_frame", run.resumedAfter >= 0 ? nlohmann::json(run.resumedAfter) : nlohmann::json(nullptr)},
                          {"checkpoint", {{"file", run.checkpoint.filename().string()}, {"frame", run.checkpointFrame},
                                          {"every_frames", run.checkpointEvery}}},
                          {"particles", simulation.particles().size()},
                          {"emitted_particles", stats.emitted},
                          {"emitter_blocked_positions", stats.emitterBlocked},
                          {"removed_by_sinks", stats.removed},
                          {"steps", stats.steps},
                          {"min_step_s", stats.minStep},
                          {"max_step_s", stats.maxStep},
                          {"active_bound_counts", bounds},
                          {"step_phases_run", phasesRun},
                          {"step_phases", phaseTimes},
                          {"solver", solver}});
  if (nlohmann::json pours = track.pourSummary(simulation); !pours.is_null())
    record.data()["stages"]["sim"]["pours"] = std::move(pours);
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
    if (bs.capHits)
      warn("the bodies' collision loop stopped at its cap (collisions.max_passes " +
               std::to_string(scene.sim.collisions.maxPasses) + ") with collisions left in " +
               std::to_string(bs.capHits) + " of " + std::to_string(stats.steps) + " steps",
           "stages.sim.bodies.collision_cap_hits");
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
  record.data()["stages"]["sim"]["warnings"] = std::move(warnings);
}

}  // namespace kurage::pipeline
