// kurage still SCENE --time T -o FILE.png: one path-traced frame at any simulated time and any
// resolution, for papers. The particles come from simulating up to T, or from an existing cache
// (--from OUT: the frame of OUT/particles nearest to T). Surfaces are built as the surface stage
// does; --spheres shows the particles themselves, coloured by kind, speed or rest-density factor.
#include "pipeline/commands/cli.h"
#include "pipeline/interrupt.h"
#include "pipeline/io/files.h"
#include "pipeline/io/json_file.h"
#include "pipeline/io/image_file.h"
#include "pipeline/io/particle_cache.h"
#include "pipeline/render_scene.h"
#include "pipeline/scene.h"
#include "pipeline/sim_frame.h"
#include "pipeline/stages.h"
#include "render/surfacing.h"
#include "sim/simulation.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <vector>

namespace kurage::pipeline {

namespace fs = std::filesystem;

namespace {

constexpr const char* kHelp =
    "usage: kurage still SCENE --time T -o FILE.png [options]\n\n"
    "Renders one frame at simulated time T (simulating up to it, or from a cache with --from).\n\n"
    "options:\n"
    "  -t, --time T         simulated time in seconds (required)\n"
    "  -o, --output FILE    PNG to write (written atomically; its folder must exist)\n"
    "  --from OUT           read OUT/particles/NNNN.vdb (the frame nearest to T, at the frame rate\n"
    "                       recorded in OUT/run.json) instead of simulating\n"
    "  --width W, --height H, --spp N, --max-depth D, --seed S\n"
    "                       override the scene's render settings (after --quality)\n"
    "  --quality Q          final (default) or preview (the scene's preview_quality)\n"
    "  --spheres BY         draw particles as spheres coloured by kind, speed or rest_density_factor\n"
    "  --clip X,Y,Z,NX,NY,NZ  remove everything (but the ground) on the side of the plane through\n"
    "                       (X,Y,Z) that the normal (NX,NY,NZ) points to: a cross-section\n"
    "  --16bit              16-bit PNG\n"
    "  --transparent        transparent background (PNG alpha)\n"
    "  --threads N          worker threads (default: all cores)\n"
    "  --force              past the scene's size limits and the step limit (docs/design/reliability.md)\n"
    "  -h, --help           this help\n";

ParticleFrame simulateTo(const Scene& scene, double time) {
  sim::Simulation simulation(scene.sim);
  simulation.setStopChecks(interruptPending);
  simulation.advanceTo(time);
  return frameFromSimulation(scene, simulation, 0);
}

}  // namespace

int commandStill(std::vector<std::string> rawArgs) {
  ArgParser args("still", std::move(rawArgs));
  if (args.flag({"-h", "--help"})) {
    std::fputs(kHelp, stdout);
    return 0;
  }
  // SIGINT/SIGTERM end the simulation after a step, the surfacing between passes, the rendering
  // between pixels: exit 128 + the signal, no image written.
  installInterruptHandlers();
  const std::optional<double> time = args.doubleOption({"-t", "--time"});
  const std::optional<std::string> output = args.option({"-o", "--output"});
  const std::optional<std::string> from = args.option({"--from"});
  const std::optional<int> width = args.intOption({"--width"}, 1, 16384);
  const std::optional<int> height = args.intOption({"--height"}, 1, 16384);
  const std::optional<int> spp = args.intOption({"--spp"}, 1, 65536);
  const std::optional<int> depth = args.intOption({"--max-depth"}, 1, 1024);
  const std::optional<int> seed = args.intOption({"--seed"}, 0, 2147483647);
  const std::optional<int> threadCount = args.intOption({"--threads"}, 1, 1024);
  const std::optional<std::string> spheres = args.option({"--spheres"});
  const std::optional<std::string> clip = args.option({"--clip"});
  const bool sixteen = args.flag({"--16bit"});
  const bool transparent = args.flag({"--transparent"});
  const bool force = args.flag({"--force"});
  const Quality quality = parseQuality(args);
  const std::vector<std::string> positional = args.positionals();
  if (positional.size() != 1) args.fail("expected one SCENE");
  if (!time) args.fail("missing --time T");
  if (!(*time >= 0.0) || !std::isfinite(*time)) args.fail("--time must be >= 0, got " + std::to_string(*time));
  if (!output) args.fail("missing -o FILE.png");
  const fs::path outFile = *output;
  if (outFile.extension() != ".png") args.fail("-o: the output must be a .png file, got " + *output);
  const fs::path outFolder = outFile.has_parent_path() ? outFile.parent_path() : fs::path(".");
  if (!fs::is_directory(outFolder)) args.fail("-o: folder " + outFolder.string() + " does not exist");

  Scene scene = loadScene(positional[0], {force});
  applyQuality(scene, quality);
  render::RenderSettings& settings = scene.render.settings;
  if (width) settings.width = *width;
  if (height) settings.height = *height;
  if (spp) settings.samplesPerPixel = *spp;
  if (depth) settings.maxDepth = *depth;
  if (seed) settings.seed = *seed;
  if (transparent) settings.transparentBackground = true;
  if (sixteen) scene.render.bitDepth = 16;
  checkSceneLimits(scene, positional[0], {force});
  if (const double steps = estimateSteps(scene, *time); !from && !force && steps > kMaxSteps) {
    char text[160];
    std::snprintf(text, sizeof text, "--time %g: simulating to it takes at least %.3g time steps, above the limit of %.3g; "
                  "--force runs it anyway", *time, steps, kMaxSteps);
    args.fail(text);
  }
  if (spheres) {
    scene.render.particles.spheres = true;
    if (*spheres == "kind") scene.render.particles.colourBy = ParticleColouring::Kind;
    else if (*spheres == "speed") scene.render.particles.colourBy = ParticleColouring::Speed;
    else if (*spheres == "rest_density_factor") scene.render.particles.colourBy = ParticleColouring::RestDensityFactor;
    else args.fail("--spheres: expected kind, speed or rest_density_factor, got " + *spheres);
  }
  if (clip) {
    float c[6];
    char tail = 0;
    if (std::sscanf(clip->c_str(), "%f,%f,%f,%f,%f,%f%c", &c[0], &c[1], &c[2], &c[3], &c[4], &c[5], &tail) != 6)
      args.fail("--clip: expected X,Y,Z,NX,NY,NZ, got " + *clip);
    scene.render.clip = {true, {c[0], c[1], c[2]}, {c[3], c[4], c[5]}};
    if (scene.render.clip.normal.norm() <= 0.0f) args.fail("--clip: the normal must not be zero");
  }
  fs::path cacheFile;
  int cacheFrame = -1;
  if (from) {
    // The run's own frame rate (a preview run may have its own, preview_quality.fps), from its
    // run.json, so that T finds the right frame whatever --quality this still is rendered at.
    try {
      const nlohmann::json run = readJson(fs::path(*from) / "run.json");
      const double fps = run.at("parameters").at("output").at("fps").get<double>();
      if (fps > 0.0 && std::isfinite(fps)) scene.output.fps = float(fps);
    } catch (const std::exception&) {
      // no readable run.json: the scene's frame rate at this --quality
    }
    cacheFrame = int(std::lround(*time * scene.output.fps));
    cacheFile = frameFile(fs::path(*from) / "particles", cacheFrame, "vdb");
    if (!fs::exists(cacheFile))
      throw std::runtime_error(cacheFile.string() + ": missing (the frame nearest to t = " + std::to_string(*time) +
                               " s); run `kurage sim` first or leave out --from");
  }

  ThreadLimit threads(threadCount.value_or(0));
  const auto start = std::chrono::steady_clock::now();
  const double frameTime = from ? scene.output.frameTime(cacheFrame) : *time;
  render::RenderStats stats;
  render::Image image;
  try {
    const ParticleFrame frame = from ? readParticleFrame(cacheFile) : simulateTo(scene, *time);
    render::Renderer renderer;
    renderer.setStopCheck(interruptPending);
    if (scene.render.particles.spheres) {
      render::RenderScene view = makeRenderScene(scene, frameTime);
      view.spheres.push_back(particleSpheres(scene, frame));
      image = renderer.render(view, settings, &stats);
    } else {
      std::vector<render::CurveSet> curves;
      if (hasChains(scene)) curves.push_back(chainTubes(scene, frame));  // chains are tubes, not surfaces
      image = renderSurfaces(scene, surfaceFrame(scene, frame, interruptPending), frameTime, &stats, curves, nullptr,
                             &renderer);
    }
  } catch (...) {
    throwIfInterrupted();  // whatever a signal cut short was interrupted
    throw;
  }
  throwIfInterrupted();
  writePng(image, outFile, settings.transparentBackground, scene.render.bitDepth);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("still: %s (%dx%d, %d spp, t = %g s%s, %.1f s)\n", outFile.string().c_str(), settings.width,
              settings.height, settings.samplesPerPixel, frameTime,
              from ? (", frame " + std::to_string(cacheFrame) + " of " + *from).c_str() : "", seconds);
  return 0;
}

}  // namespace kurage::pipeline
