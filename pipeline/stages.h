// The pipeline's stages. Each reads the files of the stage before from the output folder and
// writes its own, one file per frame, atomically:
//   sim      scene               -> OUT/particles/NNNN.vdb  (particle caches)
//   surface  OUT/particles/*.vdb -> OUT/surfaces/NNNN.vdb   (metaball level sets per material)
//   render   OUT/surfaces/*.vdb  -> OUT/frames/NNNN.png     (and OUT/particles/*.vdb for chains)
//   export   both                -> OUT/exports/...         (output.exports: PLY, OBJ, VTP)
// and OUT/run.json records the parameters in effect, library versions and stage timings
// (pipeline/run_record.h).
#pragma once

#include "pipeline/io/particle_cache.h"
#include "pipeline/progress.h"
#include "pipeline/run_record.h"
#include "pipeline/scene.h"
#include "render/image.h"
#include "render/renderer.h"
#include "render/surfacing.h"
#include "sim/particles.h"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <functional>
#include <map>
#include <string>
#include <vector>

namespace kurage::pipeline {

struct StageOptions {
  std::filesystem::path outDir;
  int firstFrame = 0;
  int lastFrame = -1;  // -1: the scene's last frame
  bool progress = false;
  // A farm task (pipeline/farm/farm.h): its record goes to OUT/records/TASK.json instead of
  // OUT/run.json, which `kurage farm merge` assembles from the records. Empty: a local run.
  std::string task;
  bool force = false;  // --force: past the scene limits (LoadOptions), and redo valid outputs
  // The simulation's checkpoints (pipeline/io/checkpoint.h): --resume continues from
  // OUT/checkpoint.bin; one is written every checkpointEvery frames (0: only after the last frame
  // and on SIGINT/SIGTERM).
  bool resume = false;
  int checkpointEvery = 10;
  // Told of each stage's progress (pipeline/progress.h): the run's report page follows it.
  ProgressObserver observer;
};

// The hash (16 hex digits) of everything in the scene that the output of `stage` ("sim",
// "surface", "render") depends on: for "sim" the simulation parameters and the frame rate, for
// "surface" those and the surface section, for "render" those and the render section (after
// --quality and command-line overrides). Stamped into every cache and surface file.
std::string stageHash(const Scene& scene, const std::string& stage);

// The frames [first, last] a stage works on, checked against the scene. Throws
// std::invalid_argument for a range outside 0 .. frameCount-1.
std::pair<int, int> frameRange(const Scene& scene, const StageOptions& options);

// Sums a per-frame stage keeps over its frames (rays, voxels, seconds), by name.
using FrameTally = std::map<std::string, double>;

// What a stage's per-frame functions work with: the scene, OUT, and the scene's stage hashes
// (stageHash), made once per stage run rather than per frame.
struct StageContext {
  StageContext(const Scene& scene, std::filesystem::path outDir);
  const Scene& scene;
  std::filesystem::path outDir;
  std::string simHash, surfaceHash, renderHash;
  // The render stage's: keeps the static geometry (the tank) from one frame to the next.
  mutable render::Renderer renderer;
  // What frame f's file of `stage` must carry: {stage, that stage's hash, f}.
  FileStamp stamp(const std::string& stage, int frame) const;
};

// A file a stage reads for a frame, and the stage that makes it (for "run `kurage sim` first").
struct StageInput {
  std::filesystem::path file;
  const char* producer;
};

// The stages as one table, read by the CLI (`kurage run|sim|surface|render`), the local runner
// and the farm (pipeline/farm): what each reads and writes per frame, and how it runs.
struct StageSpec {
  const char* name;    // "sim", "surface", "render", "export"
  const char* folder;  // OUT/<folder> holds its per-frame files
  const char* label;   // what those files are, for messages ("particle caches", ...)
  // Sequential in time (each frame needs the state of the one before): one process, never split.
  bool sequential;
  // Part of `kurage run` for this scene (export: only with output.exports).
  bool (*inRun)(const Scene& scene);
  // The files it reads for frame f (the outputs of the stages before it).
  std::vector<StageInput> (*inputs)(const StageContext& context, int frame);
  // The files it writes for frame f (empty: none per frame).
  std::vector<std::filesystem::path> (*outputs)(const StageContext& context, int frame);
  // Frame f's outputs exist whole and were made from the same inputs and settings (their stamps
  // hold this scene's stageHash and the frame): an incremental run skips the frame.
  bool (*upToDate)(const StageContext& context, int frame);
  // Makes frame f (inputs checked by the caller); adds to the tally. Null for a stage that runs
  // as a whole (sim: sequential; export).
  void (*perFrame)(const StageContext& context, int frame, FrameTally& tally);
  // The stage's entry in run.json from its tally over `framesDone` frames (per-frame stages).
  void (*summarise)(const Scene& scene, const FrameTally& tally, int framesDone, nlohmann::json& stage);
  // Runs the stage over the frames of `options` and records it.
  void (*run)(const Scene& scene, const StageOptions& options, RunRecord& record);
};

// In pipeline order: sim, surface, render, export.
const std::vector<StageSpec>& stageTable();
// The entry named `name`; throws std::invalid_argument for another name.
const StageSpec& findStage(const std::string& name);
// Runs a per-frame stage: checks its inputs, skips frames that are upToDate (unless --force),
// makes the rest in order (stopping at an interrupt), shows progress and records the stage with
// frames_done, frames_skipped and per_frame (each frame made and its seconds).
void runFrameStage(const StageSpec& stage, const Scene& scene, const StageOptions& options, RunRecord& record);

void runSimStage(const Scene& scene, const StageOptions& options, RunRecord& record);
void runSurfaceStage(const Scene& scene, const StageOptions& options, RunRecord& record);
void runRenderStage(const Scene& scene, const StageOptions& options, RunRecord& record);
// The scene's output.exports (pipeline/exports.h) from OUT/particles and OUT/surfaces.
void runExportStage(const Scene& scene, const StageOptions& options, RunRecord& record);

// Pieces of the stages, for tests and tools.
std::map<std::string, render::LevelSet> surfaceParticles(const Scene& scene, const std::filesystem::path& particleFile);
// The level sets of one frame: "fluid" and one per body (chains excepted), named after it; a
// stretched telescopic body's blobs grow with the volume its particles stand for
// (render::stretchRadiusScales, from the frame's rest density factors).
// `stop` ends it between the surfacing's passes (render::SurfacingStopped).
std::map<std::string, render::LevelSet> surfaceFrame(const Scene& scene, const ParticleFrame& frame,
                                                     const std::function<bool()>& stop = {});
// OUT/NAME.mp4 from OUT/frames (frames first..last) when the scene writes PNG frames; otherwise
// says there is no video. A movie already made from the same frames and render settings (its
// stamp) is kept unless `force`.
void encodeSceneVideo(const Scene& scene, const std::filesystem::path& outDir, int first, int last, bool force = false);

// encodeVideoAndReport (pipeline/io/video.h) that SIGINT/SIGTERM stop: ffmpeg is ended and
// Interrupted thrown, also when the signal reached ffmpeg first and made it fail.
void encodeVideoInterruptibly(const std::filesystem::path& framesFolder, int first, int count, double fps,
                              const std::filesystem::path& movie, const std::string& stamp = "", bool force = false);

// Renders the surfaces, and the tubes `curves` (chainTubes() of the frame when the scene has
// chains), with the camera at simulated time `time` (camera keys). `layers`, when given, gets
// the frame's compositing layers with the scene's object ids (render_scene.h: objectIdOfKind).
// `renderer`, when given, keeps the static geometry for the next frame; null: one of its own.
render::Image renderSurfaces(const Scene& scene, const std::map<std::string, render::LevelSet>& surfaces,
                             double time = 0.0, render::RenderStats* stats = nullptr,
                             const std::vector<render::CurveSet>& curves = {}, render::FrameLayers* layers = nullptr,
                             render::Renderer* renderer = nullptr);

}  // namespace kurage::pipeline
