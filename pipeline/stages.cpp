#include "pipeline/stages.h"

#include "pipeline/files.h"
#include "pipeline/particle_cache.h"
#include "pipeline/progress.h"
#include "pipeline/render_scene.h"
#include "render/tracer.h"
#include "sim/simulation.h"

#include <Eigen/Core>
#include <nlohmann/json.hpp>
#include <png.h>
#include <tbb/version.h>

#include <chrono>
#include <stdexcept>

namespace kurage::pipeline {

namespace fs = std::filesystem;

namespace {

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// `phaseRestDensity[k]` is the initial rest density of kind k (fluid, then each body).
ParticleFrame toFrame(const sim::ParticleSet& p, double time, int frame, const std::vector<float>& phaseRestDensity) {
  ParticleFrame f;
  f.time = time;
  f.frame = frame;
  f.px = p.x; f.py = p.y; f.pz = p.z;
  f.vx = p.vx; f.vy = p.vy; f.vz = p.vz;
  f.id = p.id;
  f.kind = p.kind;
  f.restDensityFactor.resize(p.size());
  for (size_t i = 0; i < p.size(); ++i) f.restDensityFactor[i] = p.restDensity[i] / phaseRestDensity[size_t(p.kind[i])];
  return f;
}

void requireFile(const fs::path& file, const char* producer) {
  if (!fs::exists(file))
    throw std::runtime_error(file.string() + ": missing; run `kurage " + producer + "` for these frames first");
}

}  // namespace

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

RunRecord::RunRecord(const fs::path& outDir, const Scene& scene, const std::string& sceneFile)
    : path_(outDir / "run.json") {
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

void runSimStage(const Scene& scene, const StageOptions& options, RunRecord& record) {
  const auto [first, last] = frameRange(scene, options);
  const auto start = std::chrono::steady_clock::now();
  const fs::path folder = options.outDir / "particles";
  fs::create_directories(folder);
  sim::Simulation simulation(scene.sim);
  const std::vector<float> phaseRestDensity{scene.sim.fluid.restDensity};
  Progress progress("sim", last + 1, options.progress);
  for (int f = 0; f <= last; ++f) {
    simulation.advanceTo(scene.output.frameTime(f));
    if (f >= first) writeParticleFrame(frameFile(folder, f, "vdb"), toFrame(simulation.particles(), simulation.time(), f, phaseRestDensity));
    progress.advance(f + 1);
  }
  progress.finish();

  const sim::SimStats& stats = simulation.stats();
  nlohmann::json bounds = nlohmann::json::object();
  for (size_t b = 0; b < size_t(sim::StepBound::Count); ++b)
    if (stats.boundCounts[b]) bounds[std::string(sim::stepBoundName(sim::StepBound(b)))] = stats.boundCounts[b];
  nlohmann::json stageTimes = nlohmann::json::object();
  for (size_t s = 0; s < size_t(sim::Stage::Count); ++s)
    if (stats.stageRan(sim::Stage(s))) stageTimes[std::string(sim::stageName(sim::Stage(s)))] = stats.stageSeconds[s];
  const sim::StepLimit stability = simulation.stabilityLimit();
  record.data()["derived"] = {
      {"fluid_particle_mass_kg", simulation.fluidParticleMass()},
      {"fluid_particle_mass_note", "calibrated so that a particle deep inside the initial lattice has density rho0"},
      {"support_radius_m", scene.sim.fluid.supportRadiusMetres()},
      {"speed_of_sound_m_per_s", scene.sim.fluid.speedOfSound()},
      {"stability_bound_at_rest_s", stability.step},
      {"stability_bound_at_rest_active", sim::stepBoundName(stability.bound)},
      {"frame_count", scene.output.frameCount()}};
  record.setStage("sim", {{"seconds", secondsSince(start)},
                          {"frames", {first, last}},
                          {"particles", simulation.particles().size()},
                          {"emitted_particles", stats.emitted},
                          {"emitter_blocked_positions", stats.emitterBlocked},
                          {"removed_by_sinks", stats.removed},
                          {"steps", stats.steps},
                          {"min_step_s", stats.minStep},
                          {"max_step_s", stats.maxStep},
                          {"active_bound_counts", bounds},
                          {"step_stage_seconds", stageTimes}});
  record.save();
}

std::map<std::string, render::LevelSet> surfaceParticles(const Scene& scene, const fs::path& particleFile) {
  const ParticleFrame frame = readParticleFrame(particleFile);
  std::vector<Eigen::Vector3f> fluid;
  fluid.reserve(frame.size());
  for (size_t i = 0; i < frame.size(); ++i)
    if (frame.kind[i] == 0) fluid.emplace_back(frame.px[i], frame.py[i], frame.pz[i]);
  std::map<std::string, render::LevelSet> surfaces;
  surfaces.emplace("fluid", render::buildMetaballLevelSet(fluid, scene.surface.fluid));
  return surfaces;
}

void runSurfaceStage(const Scene& scene, const StageOptions& options, RunRecord& record) {
  const auto [first, last] = frameRange(scene, options);
  const auto start = std::chrono::steady_clock::now();
  const fs::path inFolder = options.outDir / "particles";
  const fs::path outFolder = options.outDir / "surfaces";
  for (int f = first; f <= last; ++f) requireFile(frameFile(inFolder, f, "vdb"), "sim");
  fs::create_directories(outFolder);
  Progress progress("surface", last - first + 1, options.progress);
  size_t voxels = 0;
  for (int f = first; f <= last; ++f) {
    const std::map<std::string, render::LevelSet> surfaces = surfaceParticles(scene, frameFile(inFolder, f, "vdb"));
    std::map<std::string, const render::LevelSet*> grids;
    for (const auto& [name, grid] : surfaces) {
      grids[name] = &grid;
      voxels += grid.activeVoxelCount();
    }
    writeLevelSets(frameFile(outFolder, f, "vdb"), grids, scene.output.frameTime(f), f);
    progress.advance(f - first + 1);
  }
  progress.finish();
  record.setStage("surface", {{"seconds", secondsSince(start)},
                              {"frames", {first, last}},
                              {"mean_active_voxels", double(voxels) / (last - first + 1)}});
  record.save();
}

render::Image renderSurfaces(const Scene& scene, const std::map<std::string, render::LevelSet>& surfaces, double time,
                             render::RenderStats* stats) {
  std::vector<render::TriangleMesh> meshes;
  meshes.reserve(surfaces.size());
  render::RenderScene view = makeRenderScene(scene, time);
  for (const auto& [name, levelSet] : surfaces) {
    if (levelSet.empty()) continue;
    meshes.push_back(render::meshLevelSet(levelSet));
    view.meshes.push_back({&meshes.back(), scene.render.fluidMaterial});  // only "fluid" exists so far
  }
  return render::renderFrame(view, scene.render.settings, stats);
}

void runRenderStage(const Scene& scene, const StageOptions& options, RunRecord& record) {
  const auto [first, last] = frameRange(scene, options);
  const auto start = std::chrono::steady_clock::now();
  const fs::path inFolder = options.outDir / "surfaces";
  const fs::path outFolder = options.outDir / "frames";
  for (int f = first; f <= last; ++f) requireFile(frameFile(inFolder, f, "vdb"), "surface");
  fs::create_directories(outFolder);
  Progress progress("render", last - first + 1, options.progress);
  uint64_t primaryRays = 0, totalRays = 0;
  double traceSeconds = 0.0;
  for (int f = first; f <= last; ++f) {
    render::RenderStats stats;
    const render::Image image =
        renderSurfaces(scene, render::readLevelSets(frameFile(inFolder, f, "vdb")), scene.output.frameTime(f), &stats);
    primaryRays += stats.primaryRays;
    totalRays += stats.totalRays;
    traceSeconds += stats.seconds;
    render::writePng(image, frameFile(outFolder, f, "png"), scene.render.settings.transparentBackground,
                     scene.render.bitDepth);
    progress.advance(f - first + 1);
  }
  progress.finish();
  record.setStage("render", {{"seconds", secondsSince(start)},
                             {"frames", {first, last}},
                             {"width", scene.render.settings.width},
                             {"height", scene.render.settings.height},
                             {"samples", scene.render.settings.samplesPerPixel},
                             {"max_depth", scene.render.settings.maxDepth},
                             {"primary_rays", primaryRays},
                             {"total_rays", totalRays},
                             {"trace_seconds", traceSeconds},
                             {"total_mrays_per_s", traceSeconds > 0.0 ? double(totalRays) / traceSeconds * 1e-6 : 0.0}});
  record.save();
}

}  // namespace kurage::pipeline
