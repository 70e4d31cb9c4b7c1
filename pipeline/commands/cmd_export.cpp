// kurage export OUT --format F[,F...] [--frames A-B] [--threads N]: files for other tools from an
// existing run (pipeline/exports.h). The scene is the one the run recorded in OUT/run.json.
#include "pipeline/commands/cli.h"
#include "pipeline/interrupt.h"
#include "pipeline/io/files.h"
#include "pipeline/io/json_file.h"
#include "pipeline/exports.h"
#include "pipeline/scene.h"

#include <chrono>
#include <cstdio>

namespace kurage::pipeline {

namespace fs = std::filesystem;

namespace {

const char* const kHelp =
    "usage: kurage export OUT --format F[,F...] [--frames A-B] [--threads N]\n\n"
    "Writes files for Blender, ParaView, Houdini and mesh tools from the run in OUT (its particle\n"
    "caches and surfaces) into OUT/exports/. The scene is the one recorded in OUT/run.json.\n\n"
    "formats (comma separated):\n"
    "  mesh_ply       each surface (fluid, each body) as binary PLY with normals: GRID/NNNN.ply\n"
    "  mesh_obj       each surface as Wavefront OBJ: GRID/NNNN.obj\n"
    "  particles_vtp  particles as VTK XML PolyData, every attribute: particles/NNNN.vtp, particles.pvd\n"
    "  particles_ply  particles as binary PLY, every attribute: particles/NNNN.ply\n"
    "  chains_vtp     chains (oral arms) as VTK polylines: chains/NNNN.vtp, chains.pvd\n"
    "  chains_obj     chains as OBJ polylines: chains/NNNN.obj\n"
    "  all            every one of these\n\n"
    "options:\n"
    "  --frames A-B   only these frames (default: every frame of the scene)\n"
    "  --threads N    worker threads (default: all cores)\n"
    "  -h, --help     this help\n";

}  // namespace

int commandExport(std::vector<std::string> rawArgs) {
  ArgParser args("export", std::move(rawArgs));
  if (args.flag({"-h", "--help"})) {
    std::fputs(kHelp, stdout);
    return 0;
  }
  const std::optional<std::string> formats = args.option({"--format"});
  if (!formats) args.fail("--format is required; valid: " + std::string(exportFormatNames()));
  ExportSelection selection;
  try {
    selection = parseExportFormats(*formats);
  } catch (const std::invalid_argument& e) {
    args.fail(std::string("--format: ") + e.what());
  }
  StageCommandOptions options = parseStageOptions(args, false);
  const std::vector<std::string> positional = args.positionals();
  if (positional.size() != 1) args.fail("expected one OUT folder");
  options.stage.outDir = positional[0];
  const fs::path record = options.stage.outDir / "run.json";
  if (!fs::exists(record)) args.fail(record.string() + ": missing; OUT must be the folder of a kurage run");
  const nlohmann::json recorded = readJson(record);
  if (!recorded.contains("parameters")) throw SceneError(record.string(), "parameters", "missing");
  const Scene scene = parseScene(recorded["parameters"], record.string());
  const auto [first, last] = frameRange(scene, options.stage);

  ThreadLimit threads(options.threads);
  // As a stage command: one run per OUT, the temporaries of a killed run removed, SIGINT/SIGTERM
  // stop between frames (exit 128 + the signal).
  const ClaimedOutput claim(options.stage.outDir, "export " + *formats);
  const auto start = std::chrono::steady_clock::now();
  exportFrames(scene, selection, options.stage.outDir, first, last, interruptPending);
  throwIfInterrupted();
  std::printf("exports: %s (%d frames, %.1f s)\n", (options.stage.outDir / "exports").string().c_str(),
              last - first + 1, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  return 0;
}

}  // namespace kurage::pipeline
