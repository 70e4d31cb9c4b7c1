#include "pipeline/stages.h"

#include "pipeline/analysis/body_track.h"
#include "pipeline/analysis/sim_series.h"
#include "pipeline/exports.h"
#include "pipeline/interrupt.h"
#include "pipeline/io/checkpoint.h"
#include "pipeline/io/exr.h"
#include "pipeline/io/files.h"
#include "pipeline/io/image_file.h"
#include "pipeline/io/particle_cache.h"
#include "pipeline/io/stamp.h"
#include "pipeline/io/surface_file.h"
#include "pipeline/io/video.h"
#include "pipeline/progress.h"
#include "pipeline/render_scene.h"
#include "pipeline/sim_frame.h"
#include "render/renderer.h"
#include "sim/simulation.h"

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
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

namespace {

// The sim stage's own part of a checkpoint: the body records and the frame records.
std::string stageState(const BodyTrack& track, const SimSeries& series) {
  sim::StateWriter out;
  for (const std::string& part : {track.saveState(), series.saveState()})
    out.array(std::vector<char>(part.begin(), part.end()));
  return out.take();
}

void restoreStageState(const std::string& bytes, BodyTrack& track, SimSeries& series) {
  sim::StateReader in(bytes);
  std::vector<char> part;
  in.array(part, bytes.size());
  track.restoreState(std::string(part.begin(), part.end()));
  in.array(part, bytes.size());
  series.restoreState(std::string(part.begin(), part.end()));
  if (!in.done()) throw sim::StateError("checkpoint state: bytes left over after the stage's records");
}

// --resume: restores the simulation and the body records from OUT/checkpoint.bin and returns the
// frame it holds, or -1 (start at t = 0, saying why) when there is none, it lies past the frames
// asked for, or a cache it covers is missing or damaged. A damaged checkpoint, or one of other
// scene parameters or another kurage, is an error naming the file.
int resumeSimulation(const Scene& scene, const StageOptions& options, const std::string& simHash,
                     sim::Simulation& simulation, BodyTrack& track, SimSeries& series) {
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
    restoreStageState(c.stageState, track, series);
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
  const fs::path folder = outputFolder(options.outDir, "particles");
  const std::string simHash = stageHash(scene, "sim");
  sim::Simulation simulation(scene.sim);
  BodyTrack track(scene.sim, scene.name, scene.output.frameCount());
  track.start(simulation);
  // A signal ends the frame being simulated after the step it arrives in, and the checkpoint holds
  // that step's state (a resume continues bit for bit); a step whose solve runs on for more than a
  // second after it is cut short and thrown away (a resume starts at the newest checkpoint).
  simulation.setStopChecks(interruptPending, interruptPendingFor(1.0));
  SimSeries series(simulation, scene.output.frameCount());
  const fs::path checkpoint = checkpointFile(options.outDir);
  const int resumed = options.resume ? resumeSimulation(scene, options, simHash, simulation, track, series) : -1;
  int saved = resumed;  // the frame of the newest checkpoint
  const auto save = [&](int f) {
    sim::StateWriter state;
    simulation.saveState(state);
    writeCheckpoint(checkpoint, {f, simulation.time(), state.take(), stageState(track, series)}, simHash);
    saved = f;
  };
  Progress progress("sim", last + 1, options.progress, options.observer);
  for (int f = resumed + 1; f <= last; ++f) {
    if (interruptPending()) {
      if (f - 1 > saved) save(f - 1);  // a resume starts after the last frame done
      throwIfInterrupted();
    }
    try {
      simulation.advanceTo(scene.output.frameTime(f));
    } catch (const sim::Stopped& e) {
      if (!e.cutShort()) save(f - 1);  // frame f - 1 done, and the steps after it
      throwIfInterrupted();
      throw;
    }
    track.record(simulation);
    series.record(simulation);
    if (options.observer) series.write(options.outDir);  // the live report plots the frames so far
    if (f >= first) {
      ParticleFrame frame = frameFromSimulation(scene, simulation, f);
      frame.sceneHash = simHash;
      writeParticleFrame(frameFile(folder, f, "vdb"), frame);
    }
    if (f == last || (options.checkpointEvery > 0 && (f + 1) % options.checkpointEvery == 0)) save(f);
    progress.advance(f + 1, static_cast<long long>(simulation.stats().steps));
  }
  progress.finish();
  if (!scene.sim.bodies.empty()) track.write(options.outDir);
  series.write(options.outDir);

  SimStageRun run;
  run.seconds = secondsSince(start);
  run.first = first;
  run.last = last;
  run.resumedAfter = resumed;
  run.checkpoint = checkpoint;
  run.checkpointFrame = saved;
  run.checkpointEvery = options.checkpointEvery;
  recordSimStage(record, scene, simulation, track, run);
  record.save();
  throwIfInterrupted();  // a signal during the last frame (its checkpoint is written)
}

std::map<std::string, render::LevelSet> surfaceParticles(const Scene& scene, const fs::path& particleFile) {
  return surfaceFrame(scene, readParticleFrame(particleFile));
}

std::map<std::string, render::LevelSet> surfaceFrame(const Scene& scene, const ParticleFrame& frame,
                                                     const std::function<bool()>& stop) {
  // Kind 0 is the fluid, kind b + 1 the body b; chains are drawn as curves, not surfaces.
  std::vector<std::vector<Eigen::Vector3f>> byKind(scene.sim.bodies.size() + 1);
  // A stretched telescopic body's particles keep the volume they stand for (render::stretchRadiusScales).
  std::vector<std::vector<float>> factors(byKind.size());
  std::vector<Eigen::Vector3f> fluidVelocities;
  const bool airborne = scene.surface.airborne.enabled;
  const bool hasFactors = frame.restDensityFactor.size() == frame.size();
  for (size_t i = 0; i < frame.size(); ++i) {
    const size_t kind = size_t(frame.kind[i]);
    if (kind < byKind.size()) byKind[kind].emplace_back(frame.px[i], frame.py[i], frame.pz[i]);
    if (kind > 0 && kind < byKind.size()) factors[kind].push_back(hasFactors ? frame.restDensityFactor[i] : 1.0f);
    if (airborne && kind == 0) fluidVelocities.emplace_back(frame.vx[i], frame.vy[i], frame.vz[i]);
  }
  const std::vector<float> fluidScales =
      airborne ? render::airborneRadiusScales(byKind[0], fluidVelocities, scene.surface.fluid.radius,
                                              scene.sim.fluid.spacing, scene.surface.airborne)
               : std::vector<float>{};
  // Errors name the scene key whose voxel size is too fine for the positions or the memory.
  const auto build = [&](const std::vector<Eigen::Vector3f>& positions, const std::vector<float>& scales,
                         const render::MetaballParams& params, const char* key, float clipMargin) {
    render::LevelSet levelSet;
    const auto named = [&](const std::string& what) {
      char size[32];
      std::snprintf(size, sizeof size, "%g", double(params.voxelSize));
      return std::string(key) + " = " + size + " m: " + what;
    };
    try {
      levelSet = render::buildMetaballLevelSet(positions, scales, params, stop);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(named(e.what()));
    } catch (const std::bad_alloc&) {
      throw std::runtime_error(named("out of memory surfacing " + std::to_string(positions.size()) +
                                     " particles (`kurage check` estimates the memory of each stage)"));
    }
    if (scene.surface.clipToContainer) {
      const Eigen::Vector3f margin = Eigen::Vector3f::Constant(clipMargin);
      render::intersectWithBox(levelSet, scene.sim.container.min - margin, scene.sim.container.max + margin);
    }
    return levelSet;
  };
  std::map<std::string, render::LevelSet> surfaces;
  // The clip margins: a body's outside the fluid's (SurfaceParams::clipToContainer).
  const float fluidMargin = 0.25f * scene.surface.fluid.voxelSize;
  const float bodyMargin = fluidMargin + 0.25f * scene.surface.bodies.voxelSize;
  surfaces.emplace("fluid",
                   build(byKind[0], fluidScales, scene.surface.fluid, "surface.fluid.voxel_size", fluidMargin));
  for (size_t b = 0; b < scene.sim.bodies.size(); ++b)
    if (scene.sim.bodies[b].shape != sim::BodyShape::Chain)
      surfaces.emplace(scene.sim.bodies[b].name,
                       build(byKind[b + 1], render::stretchRadiusScales(factors[b + 1]), scene.surface.bodies,
                             "surface.bodies.voxel_size", bodyMargin));
  return surfaces;
}

namespace {

fs::path cacheFile(const fs::path& outDir, int f) { return frameFile(outDir / "particles", f, "vdb"); }
fs::path surfaceFile(const fs::path& outDir, int f) { return frameFile(outDir / "surfaces", f, "vdb"); }

void surfaceOneFrame(const StageContext& c, int f, FrameTally& tally) {
  const fs::path cache = cacheFile(c.outDir, f);
  const ParticleFrame frame = readParticleFrame(cache, c.stamp("sim", f));
  std::map<std::string, render::LevelSet> surfaces;
  try {
    surfaces = surfaceFrame(c.scene, frame, interruptPending);  // a signal ends it between passes
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(cache.string() + ": " + e.what());
  }
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
                             render::FrameLayers* layers, render::Renderer* renderer) {
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
  view.curves.insert(view.curves.end(), curves.begin(), curves.end());  // after the faucets
  if (layers) layers->objectNames = objectNames(scene);
  return renderer ? renderer->render(view, scene.render.settings, stats, layers)
                  : render::renderFrame(view, scene.render.settings, stats, layers);
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
                     &stats, curves, scene.render.outputs.exr ? &layers : nullptr, &c.renderer);
  tally["primary_rays"] += double(stats.primaryRays);
  tally["total_rays"] += double(stats.totalRays);
  tally["trace_seconds"] += stats.seconds;
  tally["bvh_build_seconds"] += stats.buildSeconds;
  tally["static_builds"] += stats.staticBuilt ? 1.0 : 0.0;
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
  stage["bvh_build_seconds"] = get("bvh_build_seconds");  // of trace_seconds; the static part only when rebuilt
  stage["static_builds"] = uint64_t(get("static_builds"));
  stage["total_mrays_per_s"] = get("trace_seconds") > 0.0 ? get("total_rays") / get("trace_seconds") * 1e-6 : 0.0;
}

}  // namespace

void runRenderStage(const Scene& scene, const StageOptions& options, RunRecord& record) {
  runFrameStage(findStage("render"), scene, options, record);
}

void runExportStage(const Scene& scene, const StageOptions& options, RunRecord& record) {
  const auto [first, last] = frameRange(scene, options);
  const auto start = std::chrono::steady_clock::now();
  exportFrames(scene, scene.output.exports, options.outDir, first, last, interruptPending);
  record.setStage("export", {{"frames", last - first + 1}, {"seconds", secondsSince(start)}});
  record.save();
  throwIfInterrupted();
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
  outputFolder(options.outDir, stage.folder);
  Progress progress(stage.name, int(todo.size()), options.progress, options.observer);
  FrameTally tally;
  int done = 0;
  // Each frame made and its seconds (the frames skipped as up to date are not listed).
  nlohmann::json perFrame = {{"frame", nlohmann::json::array()}, {"seconds", nlohmann::json::array()}};
  context.renderer.setStopCheck(interruptPending);  // a signal ends a frame between pixels
  for (int f : todo) {
    throwIfInterrupted();
    const auto frameStart = std::chrono::steady_clock::now();
    try {
      stage.perFrame(context, f, tally);
    } catch (const std::bad_alloc&) {
      throw std::runtime_error(std::string(stage.name) + ": frame " + std::to_string(f) +
                               ": out of memory (`kurage check` estimates the memory of each stage)");
    } catch (...) {
      throwIfInterrupted();  // whatever a signal cut short (a frame stopped, ffmpeg ended) was interrupted
      throw;
    }
    perFrame["frame"].push_back(f);
    perFrame["seconds"].push_back(secondsSince(frameStart));
    progress.advance(++done);
  }
  progress.finish();
  nlohmann::json entry = {{"seconds", secondsSince(start)},
                          {"frames", {first, last}},
                          {"frames_done", done},
                          {"frames_skipped", (last - first + 1) - done},
                          {"per_frame", std::move(perFrame)}};
  stage.summarise(scene, tally, done, entry);
  record.setStage(stage.name, std::move(entry));
  record.save();
  throwIfInterrupted();  // a signal during the last frame: the frames are whole, the run is not complete
}

void encodeVideoInterruptibly(const fs::path& framesFolder, int first, int count, double fps, const fs::path& movie,
                              const std::string& stamp, bool force) {
  // A signal ends ffmpeg (stop), or reaches it too (Ctrl-C goes to the process group) and makes
  // it fail: either way the run was interrupted, not failed.
  try {
    encodeVideoAndReport(framesFolder, first, count, fps, movie, stamp, force, interruptPending);
  } catch (const IoError&) {
    throwIfInterrupted();
    throw;
  }
  throwIfInterrupted();
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
  encodeVideoInterruptibly(outDir / "frames", first, last - first + 1, scene.output.fps,
                           outDir / (scene.name + ".mp4"), stamp, force);
}

}  // namespace kurage::pipeline
