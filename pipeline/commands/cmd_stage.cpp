// kurage run | sim | surface | render SCENE -o OUT
#include "pipeline/commands/cli.h"
#include "pipeline/estimate.h"
#include "pipeline/interrupt.h"
#include "pipeline/io/files.h"
#include "pipeline/io/process.h"
#include "pipeline/io/run_lock.h"
#include "pipeline/report/run_report.h"
#include "pipeline/scene.h"
#include "pipeline/stages.h"
#include "sim/simulation.h"

#include <cstdio>
#include <optional>

namespace kurage::pipeline {

namespace {

// A fixed step above the scene's own stability bound: a warning, or with --strict an error.
void checkFixedStep(const Scene& scene, const std::string& file, bool strict) {
  const sim::TimeStepParams& ts = scene.sim.timeStep;
  if (ts.mode != sim::TimeStepMode::Fixed) return;
  const sim::Simulation probe(scene.sim);
  const sim::StepLimit bound = probe.stabilityLimit();
  if (ts.fixedStep <= bound.step) return;
  const std::string message = "the fixed step " + std::to_string(ts.fixedStep) + " s exceeds the " +
                              std::string(sim::stepBoundName(bound.bound)) + " stability bound " +
                              std::to_string(bound.step) + " s of this scene's parameters";
  if (strict) throw SceneError(file, "time_step.fixed_step", message + " (--strict)");
  std::fprintf(stderr, "kurage: warning: %s: time_step.fixed_step: %s\n", file.c_str(), message.c_str());
}

}  // namespace

int commandStage(const std::string& name, std::vector<std::string> rawArgs) {
  std::string commandLine = "kurage " + name;
  for (const std::string& a : rawArgs) commandLine.append(" ").append(shellWord(a, false));
  ArgParser args(name, std::move(rawArgs));
  if (args.flag({"-h", "--help"})) {
    std::printf("usage: kurage %s SCENE -o OUT [--frames A-B] [--threads N] [--progress] [--strict]\n"
                "       [--quality preview|final] [--width W --height H --spp N --max-depth D]%s\n\n",
                name.c_str(), name == "run" || name == "render" ? " [--no-video]" : "");
    if (name == "run")
      std::printf("Simulates, surfaces and renders: OUT/particles, OUT/surfaces, OUT/frames, and OUT/NAME.mp4\n"
                  "(NAME = the scene's name) when ffmpeg is on the PATH; the scene's output.exports into\n"
                  "OUT/exports (see `kurage export --help`).\n\n");
    if (name == "sim") std::printf("Simulates only: OUT/particles/NNNN.vdb.\n\n");
    if (name == "surface") std::printf("Metaball level sets from OUT/particles: OUT/surfaces/NNNN.vdb.\n\n");
    if (name == "render")
      std::printf("Frames from OUT/surfaces: OUT/frames/NNNN.png, and OUT/NAME.mp4 when ffmpeg is on the PATH.\n\n");
    std::printf("options:\n%s  --strict           a fixed time step above the scene's stability bound is an error\n"
                "  --width W, --height H, --spp N, --max-depth D\n"
                "                     override the scene's render resolution, samples per pixel and path depth\n"
                "                     (after --quality)\n%s"
                "  --no-video         (run, render) PNG frames only, no OUT/NAME.mp4\n\n"
                "OUT/report.html shows the run as a page, kept current while it runs (`kurage report --help`).\n",
                kStageOptionsHelp, kQualityHelp);
    return 0;
  }
  const bool strict = args.flag({"--strict"});
  const Quality quality = parseQuality(args);
  const bool video = !args.flag({"--no-video"}) && (name == "run" || name == "render");
  const std::optional<int> width = args.intOption({"--width"}, 1, 16384);
  const std::optional<int> height = args.intOption({"--height"}, 1, 16384);
  const std::optional<int> spp = args.intOption({"--spp"}, 1, 65536);
  const std::optional<int> depth = args.intOption({"--max-depth"}, 1, 1024);
  StageCommandOptions options = parseStageOptions(args, true);
  const std::vector<std::string> positional = args.positionals();
  if (positional.size() != 1) args.fail("expected one SCENE");
  const std::string& sceneFile = positional[0];

  // Everything is validated before the output folder is touched.
  Scene scene = loadScene(sceneFile, {options.stage.force});
  applyQuality(scene, quality);
  if (width) scene.render.settings.width = *width;
  if (height) scene.render.settings.height = *height;
  if (spp) scene.render.settings.samplesPerPixel = *spp;
  if (depth) scene.render.settings.maxDepth = *depth;
  checkSceneLimits(scene, sceneFile, {options.stage.force});  // after --width, --height
  checkedFrameRange(args, scene, options.stage);
  checkFixedStep(scene, sceneFile, strict);

  ThreadLimit threads(options.threads);
  // One run per OUT (held until the process ends); SIGINT/SIGTERM stop at the next frame. A farm
  // task takes no lock: its job dependencies order the stages, its frames are its own, and its
  // record is its own file (OUT/records/TASK.json).
  const ClaimedOutput claim(options.stage.outDir, name + " " + sceneFile, options.stage.task);
  RunRecord record(options.stage.outDir, scene, sceneFile, options.stage.task);
  record.data()["threads"] = ThreadLimit::current();
  record.data()["quality"] = quality == Quality::Preview ? "preview" : "final";
  record.data()["command"] = name;
  record.data()["command_line"] = commandLine;
  record.data()["status"] = "running";
  // `run` is every stage of the table the scene needs, in order; the others are one stage.
  const bool all = name == "run";
  std::vector<const StageSpec*> stages;
  nlohmann::json planned = nlohmann::json::array();
  for (const StageSpec& stage : stageTable())
    if (all ? stage.inRun(scene) : name == stage.name) {
      stages.push_back(&stage);
      planned.push_back(stage.name);
    }
  if (video) planned.push_back("film");
  record.data()["stages_planned"] = planned;
  record.save();
  // OUT/report.html follows the run (a farm task leaves it to `kurage farm merge`).
  std::optional<LiveRunReport> report;
  if (options.stage.task.empty()) {
    report.emplace(options.stage.outDir);
    options.stage.observer = report->observer();
  }
  // `run` says how long it expects to take: from the model at its start (`kurage check
  // --estimate`), then from each stage's first measured frame.
  std::optional<RunForecast> forecast;
  if (all) {
    RunSize size = runSize(scene, sim::Simulation(scene.sim), ThreadLimit::current(), video);
    const auto [first, last] = frameRange(scene, options.stage);
    size.frames = last - first + 1;
    forecast.emplace(estimateRun(size));
    std::printf("run: expected (model): %s\n", forecast->line().c_str());
    std::fflush(stdout);
    options.stage.observer = [&forecast, page = options.stage.observer](const ProgressState& told) {
      ProgressState state = told;
      const std::string measured = forecast->observe(state);
      if (!measured.empty()) {
        std::printf("run: %s; expected left: %s\n", measured.c_str(), forecast->line().c_str());
        std::fflush(stdout);
      }
      if (page) page(state);
    };
  }
  try {
    for (const StageSpec* stage : stages) stage->run(scene, options.stage, record);
    const StageSpec& shown = findStage(all ? "render" : name);
    std::printf("%s: %s\n", shown.label, (options.stage.outDir / shown.folder).string().c_str());
    if (video) {
      if (options.stage.observer) options.stage.observer({"film", 0, 1, 0.0, -1.0});
      const auto [first, last] = frameRange(scene, options.stage);
      encodeSceneVideo(scene, options.stage.outDir, first, last, options.stage.force);
    }
    throwIfInterrupted();  // whatever came after the last check: the run is not complete
  } catch (const std::exception& e) {
    // run.json says how the run ended; a failure to record that must not hide the first error.
    record.data()["status"] = dynamic_cast<const Interrupted*>(&e) ? "interrupted" : "failed";
    record.data()["error"] = e.what();
    try {
      record.save();
    } catch (const std::exception&) {
    }
    if (report) report->finish();
    throw;
  }
  record.data()["status"] = "complete";
  record.data().erase("error");
  record.save();
  if (report) {
    report->finish();
    std::printf("report: %s\n", (options.stage.outDir / "report.html").string().c_str());
  }
  return 0;
}

}  // namespace kurage::pipeline
