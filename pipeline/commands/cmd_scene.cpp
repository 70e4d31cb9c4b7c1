// kurage check SCENE [--estimate], kurage schema
#include "pipeline/commands/cli.h"
#include "pipeline/estimate.h"
#include "pipeline/scene.h"
#include "pipeline/thread_limit.h"
#include "sim/simulation.h"

#include <nlohmann/json.hpp>

#include <cstdio>
#include <optional>

namespace kurage::pipeline {

int commandCheck(std::vector<std::string> rawArgs) {
  ArgParser args("check", std::move(rawArgs));
  if (args.flag({"-h", "--help"})) {
    std::printf("usage: kurage check SCENE [--force] [--estimate [--quality preview|final] [--threads N] [--json]]\n\n"
                "Validates SCENE (keys, types, ranges, consistency, the size limits of docs/design/reliability.md) "
                "and exits 0 if it is valid, 2 with a message naming the file and the JSON path if not. --force "
                "lifts the soft size limits.\n\n"
                "--estimate also says, without running it, what `kurage run` of SCENE does: its particles at t = 0, "
                "frames, time steps, and the minutes of each stage (sim, surface, render, encode) from a model of "
                "the development machine's speed (pipeline/estimate.h; docs/guide/cli.md says how good it is).\n"
                "%s  --threads N        the threads the run will use (default: all cores); the model scales "
                "linearly\n  --json             the estimate as one JSON object\n",
                kQualityHelp);
    return 0;
  }
  const bool force = args.flag({"--force"});
  const bool estimate = args.flag({"--estimate"});
  const Quality quality = parseQuality(args);
  const std::optional<int> threads = args.intOption({"--threads"}, 1, 4096);
  const bool json = args.flag({"--json"});
  const std::vector<std::string> positional = args.positionals();
  if (positional.size() != 1) args.fail("expected one SCENE");
  if (!estimate && (json || threads || quality != Quality::Final)) args.fail("--quality, --threads and --json go with --estimate");
  Scene scene = loadScene(positional[0], {force});
  const sim::Simulation probe(scene.sim);
  const SceneEstimate e = estimateScene(scene);
  if (!json)
    std::printf("%s: valid (%zu particles, %d frames, at least %.3g steps; memory up to %.2g GB simulating, "
                "%.2g GB surfacing, %.2g GB rendering)\n",
                positional[0].c_str(), probe.particles().size(), scene.output.frameCount(), e.steps,
                e.memoryBytes / 1e9, e.surfaceBytes / 1e9, e.renderBytes / 1e9);
  if (!estimate) return 0;
  applyQuality(scene, quality);
  const RunSize size = runSize(scene, probe, threads ? *threads : ThreadLimit::current(), true);
  const RunEstimate run = estimateRun(size);
  const MachineSpeed& machine = kDevelopmentMachine;
  const char* qualityName = quality == Quality::Preview ? "preview" : "final";
  if (json) {
    nlohmann::json minutes;
    for (size_t s = 0; s < kStageNames.size(); ++s) minutes[kStageNames[s]] = run.seconds[s] / 60.0;
    minutes["total"] = run.totalSeconds() / 60.0;
    const nlohmann::json out = {{"scene", positional[0]},
                                {"quality", qualityName},
                                {"machine", machine.machine},
                                {"threads", size.threads},
                                {"particles", size.particles},
                                {"frames", size.frames},
                                {"steps", run.steps},
                                {"steps_per_frame", stepsPerFrame(size.frameInterval, size.step)},
                                {"step_s", size.step},
                                {"minutes", minutes}};
    std::printf("%s\n", out.dump(2).c_str());
    return 0;
  }
  std::printf("estimate (%s quality, %d threads; speeds of the %s):\n", qualityName, size.threads, machine.machine);
  std::printf("  particles  %.0f at t = 0\n", size.particles);
  std::printf("  frames     %.0f at %g fps\n", size.frames, double(scene.output.fps));
  std::printf("  steps      %.0f (%.0f a frame at a step of %.3g s)\n", run.steps,
              stepsPerFrame(size.frameInterval, size.step), size.step);
  for (size_t s = 0; s < kStageNames.size(); ++s)
    std::printf("  %-10s %.1f min (%.3g s)\n", kStageNames[s], run.seconds[s] / 60.0, run.seconds[s]);
  std::printf("  total      %.1f min (%.3g s)\n", run.totalSeconds() / 60.0, run.totalSeconds());
  return 0;
}

int commandSchema(std::vector<std::string> rawArgs) {
  ArgParser args("schema", std::move(rawArgs));
  if (args.flag({"-h", "--help"})) {
    std::printf("usage: kurage schema\n\nPrints the JSON Schema of scene files (scenes/schema.json is this output).\n");
    return 0;
  }
  if (!args.positionals().empty()) args.fail("takes no arguments");
  std::printf("%s\n", sceneSchema().dump(2).c_str());
  return 0;
}

}  // namespace kurage::pipeline
