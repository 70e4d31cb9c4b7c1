// kurage: scene file -> particle simulation -> metaball surfaces -> ray-traced frames.
// Only this file decides to exit; commands and libraries report errors to their caller.
#include "pipeline/commands/cli.h"
#include "pipeline/interrupt.h"
#include "pipeline/scene.h"
#include "sim/simulation.h"

#include <csignal>
#include <cstdio>
#include <string>
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
    "  preview SCENE -o OUT  particles as spheres (OpenGL): OUT/preview/NNNN.png, preview.mp4\n"
    "  export OUT --format F files for Blender, ParaView, mesh tools: OUT/exports/ (PLY, OBJ, VTP)\n"
    "  farm SCENE -o OUT     Slurm job scripts (sim, a job array of frames, merge); --submit; farm status OUT\n"
    "  still SCENE --time T -o FILE.png   one path-traced frame at any time and resolution\n"
    "  study STUDY -o OUT    accuracy against cost: a sweep of scene knobs, OUT/study.csv, .png, .md\n"
    "  report OUT            OUT/report.html: the run as a page (run and the stages write it too)\n"
    "  figures DIR           the paper's Figs. 2, 3 and 5 from its three experiments, into DIR\n"
    "  check SCENE           validate a scene file and exit\n"
    "  schema                print the JSON Schema of scene files\n"
    "  bench sim             simulation throughput (particle-steps per second)\n"
    "  bench render          path tracer throughput (Mrays/s, s/frame at 1280x720, 1 and 2 threads)\n"
    "  bench surface         surfacing throughput (particles per second to level sets, meshes)\n"
    "  --version             versions of kurage and its libraries\n"
    "\n"
    "Run `kurage <command> --help` for the options of a command.\n";

int dispatch(const std::string& command, std::vector<std::string> args) {
  if (command == "-h" || command == "--help" || command == "help") {
    std::fputs(kUsage, stdout);
    return 0;
  }
  if (command == "--version") {
    std::printf("%s\n", versionInfo().dump(2).c_str());
    return 0;
  }
  if (command == "run" || command == "sim" || command == "surface" || command == "render")
    return commandStage(command, std::move(args));
  if (command == "check") return commandCheck(std::move(args));
  if (command == "schema") return commandSchema(std::move(args));
  if (command == "bench") return commandBench(std::move(args));
  if (command == "still") return commandStill(std::move(args));
  if (command == "preview") return commandPreview(std::move(args));
  if (command == "export") return commandExport(std::move(args));
  if (command == "farm") return commandFarm(std::move(args));
  if (command == "study") return commandStudy(std::move(args));
  if (command == "report") return commandReport(std::move(args));
  if (command == "figures") return commandFigures(std::move(args));
  throw UsageError("unknown command " + command);
}

}  // namespace

int main(int argc, char** argv) {
  // A file-size limit (ulimit -f) must not kill the process mid-write: with SIGXFSZ ignored the
  // write fails with EFBIG, and the checked write (pipeline/io/files.h) reports it naming the
  // file, removes its temporary, and run.json says the run failed.
  std::signal(SIGXFSZ, SIG_IGN);
  try {
    if (argc < 2) throw UsageError("missing command");
    return dispatch(argv[1], std::vector<std::string>(argv + 2, argv + argc));
  } catch (const UsageError& e) {
    std::fprintf(stderr, "kurage: %s\n(see `kurage --help`)\n", e.what());
    return 2;
  } catch (const SceneError& e) {
    std::fprintf(stderr, "kurage: scene error: %s\n", e.what());
    return 2;
  } catch (const Interrupted& e) {
    std::fprintf(stderr, "kurage: %s\n", e.what());
    return 128 + e.signal();
  } catch (const kurage::sim::SimulationError& e) {
    std::fprintf(stderr, "kurage: simulation stopped: %s\n", e.what());
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "kurage: error: %s\n", e.what());
    return 1;
  }
}
