// kurage check SCENE, kurage schema
#include "pipeline/commands/cli.h"
#include "pipeline/scene.h"
#include "sim/simulation.h"

#include <cstdio>

namespace kurage::pipeline {

int commandCheck(std::vector<std::string> rawArgs) {
  ArgParser args("check", std::move(rawArgs));
  if (args.flag({"-h", "--help"})) {
    std::printf("usage: kurage check SCENE [--force]\n\nValidates SCENE (keys, types, ranges, consistency, the size "
                "limits of docs/design/reliability.md) and exits 0 if it is valid, 2 with a message naming the file and the "
                "JSON path if not. --force lifts the soft size limits.\n");
    return 0;
  }
  const bool force = args.flag({"--force"});
  const std::vector<std::string> positional = args.positionals();
  if (positional.size() != 1) args.fail("expected one SCENE");
  const Scene scene = loadScene(positional[0], {force});
  const sim::Simulation probe(scene.sim);
  const SceneEstimate e = estimateScene(scene);
  std::printf("%s: valid (%zu particles, %d frames, at least %.3g steps; memory up to %.2g GB simulating, "
              "%.2g GB surfacing, %.2g GB rendering)\n",
              positional[0].c_str(), probe.particles().size(), scene.output.frameCount(), e.steps,
              e.memoryBytes / 1e9, e.surfaceBytes / 1e9, e.renderBytes / 1e9);
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
