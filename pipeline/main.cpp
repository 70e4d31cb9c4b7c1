// kurage: scene file -> particle simulation -> metaball surfaces -> ray-traced frames.
// Only this file decides to exit; the libraries report errors to their caller.
#include "pipeline/scene.h"
#include "pipeline/stages.h"
#include "sim/simulation.h"

#include <tbb/global_control.h>

#include <cstdio>
#include <cstring>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <unistd.h>
#include <vector>

namespace {

using namespace kurage::pipeline;

constexpr const char* kUsage =
    "usage: kurage <command> [options]\n"
    "\n"
    "commands:\n"
    "  run SCENE -o OUT      simulate, surface and render every frame\n"
    "  sim SCENE -o OUT      simulate only: OUT/particles/NNNN.vdb\n"
    "  surface SCENE -o OUT  metaball level sets from the caches: OUT/surfaces/NNNN.vdb\n"
    "  render SCENE -o OUT   frames from the level sets: OUT/frames/NNNN.png\n"
    "  check SCENE           validate a scene file and exit\n"
    "  schema                print the JSON Schema of scene files\n"
    "\n"
    "Run `kurage <command> --help` for the options of a command.\n";

constexpr const char* kStageOptions =
    "options:\n"
    "  -o, --output OUT   output folder (created if missing)\n"
    "  --frames A-B       only frames A to B (0-based, inclusive); the simulation still starts at t = 0\n"
    "  --threads N        worker threads (default: all cores)\n"
    "  --progress         show progress on stderr even when it is not a terminal\n"
    "  -h, --help         this help\n";

struct Command {
  std::string name;
  std::string scene;
  StageOptions stage;
  int threads = 0;
  bool help = false;
};

[[noreturn]] void usageError(const std::string& message) {
  std::fprintf(stderr, "kurage: %s\n(see `kurage --help`)\n", message.c_str());
  std::exit(2);
}

Command parse(int argc, char** argv) {
  Command c;
  if (argc < 2) usageError("missing command");
  c.name = argv[1];
  c.stage.progress = isatty(STDERR_FILENO);
  for (int i = 2; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&]() -> std::string {
      if (i + 1 >= argc) usageError(a + " needs a value");
      return argv[++i];
    };
    if (a == "-h" || a == "--help") c.help = true;
    else if (a == "-o" || a == "--output") c.stage.outDir = next();
    else if (a == "--progress") c.stage.progress = true;
    else if (a == "--threads") {
      const std::string v = next();
      try { c.threads = std::stoi(v); } catch (...) { usageError("--threads: not a number: " + v); }
      if (c.threads < 1) usageError("--threads must be >= 1");
    } else if (a == "--frames") {
      const std::string v = next();
      int first = 0, last = 0;
      char tail = 0;
      if (std::sscanf(v.c_str(), "%d-%d%c", &first, &last, &tail) == 2) {
        c.stage.firstFrame = first;
        c.stage.lastFrame = last;
      } else if (std::sscanf(v.c_str(), "%d%c", &first, &tail) == 1) {
        c.stage.firstFrame = c.stage.lastFrame = first;
      } else {
        usageError("--frames: expected A-B or A, got " + v);
      }
      if (c.stage.firstFrame < 0 || c.stage.lastFrame < c.stage.firstFrame) usageError("--frames: bad range " + v);
    } else if (!a.empty() && a[0] == '-') usageError("unknown option " + a);
    else if (c.scene.empty()) c.scene = a;
    else usageError("unexpected argument " + a);
  }
  return c;
}

int stageCommand(const Command& c) {
  if (c.help) {
    std::printf("usage: kurage %s SCENE -o OUT [--frames A-B] [--threads N] [--progress]\n\n%s", c.name.c_str(),
                kStageOptions);
    return 0;
  }
  if (c.scene.empty()) usageError(c.name + ": missing SCENE");
  if (c.stage.outDir.empty()) usageError(c.name + ": missing -o OUT");
  // Everything is validated before the output folder is touched.
  const Scene scene = loadScene(c.scene);
  frameRange(scene, c.stage);
  std::unique_ptr<tbb::global_control> threads;
  if (c.threads > 0)
    threads = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, size_t(c.threads));
  std::filesystem::create_directories(c.stage.outDir);
  RunRecord record(c.stage.outDir, scene, c.scene);
  record.data()["threads"] = c.threads > 0 ? c.threads
                                           : int(tbb::global_control::active_value(
                                                 tbb::global_control::max_allowed_parallelism));
  if (c.name == "run" || c.name == "sim") runSimStage(scene, c.stage, record);
  if (c.name == "run" || c.name == "surface") runSurfaceStage(scene, c.stage, record);
  if (c.name == "run" || c.name == "render") {
    runRenderStage(scene, c.stage, record);
    std::printf("frames: %s\n", (c.stage.outDir / "frames").string().c_str());
  }
  if (c.name == "sim") std::printf("particle caches: %s\n", (c.stage.outDir / "particles").string().c_str());
  if (c.name == "surface") std::printf("surfaces: %s\n", (c.stage.outDir / "surfaces").string().c_str());
  return 0;
}

int run(int argc, char** argv) {
  const Command c = parse(argc, argv);
  if (c.name == "-h" || c.name == "--help" || c.name == "help") {
    std::fputs(kUsage, stdout);
    return 0;
  }
  if (c.name == "--version") {
    std::printf("%s\n", versionInfo().dump(2).c_str());
    return 0;
  }
  if (c.name == "run" || c.name == "sim" || c.name == "surface" || c.name == "render") return stageCommand(c);
  if (c.name == "check") {
    if (c.help) {
      std::printf("usage: kurage check SCENE\n\nValidates SCENE (keys, types, ranges, consistency) and exits 0 if it "
                  "is valid, 2 with a message naming the file and JSON path if not.\n");
      return 0;
    }
    if (c.scene.empty()) usageError("check: missing SCENE");
    const Scene scene = loadScene(c.scene);
    kurage::sim::Simulation probe(scene.sim);
    std::printf("%s: valid (%zu particles, %d frames)\n", c.scene.c_str(), probe.particles().size(),
                scene.output.frameCount());
    return 0;
  }
  if (c.name == "schema") {
    if (c.help) {
      std::printf("usage: kurage schema\n\nPrints the JSON Schema of scene files (scenes/schema.json is this output).\n");
      return 0;
    }
    std::printf("%s\n", sceneSchema().dump(2).c_str());
    return 0;
  }
  usageError("unknown command " + c.name);
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const SceneError& e) {
    std::fprintf(stderr, "kurage: scene error: %s\n", e.what());
    return 2;
  } catch (const kurage::sim::SimulationError& e) {
    std::fprintf(stderr, "kurage: simulation stopped: %s\n", e.what());
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "kurage: error: %s\n", e.what());
    return 1;
  }
}
