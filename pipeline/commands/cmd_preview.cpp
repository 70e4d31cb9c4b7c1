// kurage preview SCENE -o OUT: the particle caches OUT/particles/NNNN.vdb drawn as shaded
// spheres through OSMesa (render/preview.h) into OUT/preview/NNNN.png, and OUT/preview.mp4
// when ffmpeg is on the PATH. A quick look at a simulation without surfacing or ray tracing.
//
// Spheres have the radius of half the fluid's particle spacing; they are coloured by kind
// (fluid blue, bodies from a fixed palette) or by speed (--color speed: blue at
// rest to red at --max-speed, default the free-fall speed from the container's top,
// sqrt(2 |g| height)). Camera and resolution come from the scene's render settings; the light is
// fixed (from above, over the camera's shoulder) and the background a flat pale grey-blue.
#include "pipeline/commands/cli.h"
#include "pipeline/interrupt.h"
#include "pipeline/io/files.h"
#include "pipeline/io/image_file.h"
#include "pipeline/io/particle_cache.h"
#include "pipeline/stages.h"
#include "pipeline/progress.h"
#include "pipeline/scene.h"
#include "pipeline/io/video.h"
#include "render/preview.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

extern char** environ;

namespace kurage::pipeline {

namespace {

namespace fs = std::filesystem;

enum class ColourBy { Kind, Speed };

Eigen::Vector3f kindColour(int32_t kind) {
  if (kind <= 0) return {0.15f, 0.35f, 0.85f};
  static const Eigen::Vector3f palette[] = {{0.9f, 0.45f, 0.1f}, {0.2f, 0.7f, 0.25f}, {0.85f, 0.15f, 0.2f},
                                            {0.6f, 0.3f, 0.8f},  {0.9f, 0.8f, 0.15f}, {0.4f, 0.4f, 0.4f}};
  return palette[size_t(kind - 1) % std::size(palette)];
}

// Blue (0) - cyan - green - yellow - red (1), linear RGB.
Eigen::Vector3f speedColour(float t) {
  t = std::clamp(t, 0.0f, 1.0f);
  static const Eigen::Vector3f stops[] = {{0.05f, 0.15f, 0.8f}, {0.05f, 0.6f, 0.7f}, {0.1f, 0.7f, 0.1f},
                                          {0.85f, 0.75f, 0.05f}, {0.8f, 0.05f, 0.03f}};
  const float x = t * 4.0f;
  const int i = std::min(3, int(x));
  return stops[i] + (x - float(i)) * (stops[i + 1] - stops[i]);
}

}  // namespace

int commandPreview(std::vector<std::string> rawArgs) {
  ArgParser args("preview", std::move(rawArgs));
  if (args.flag({"-h", "--help"})) {
    std::printf("usage: kurage preview SCENE -o OUT [--color kind|speed] [--max-speed V] [--width W] [--height H]\n"
                "                      [--frames A-B] [--threads N] [--progress] [--no-video]\n\n"
                "Draws the particle caches OUT/particles/NNNN.vdb (from `kurage sim`) as shaded spheres with\n"
                "OpenGL (OSMesa, headless): OUT/preview/NNNN.png, and OUT/preview.mp4 when ffmpeg is on the\n"
                "PATH (--no-video skips it).\n\noptions:\n"
                "  --color kind|speed colour by particle kind (default) or by speed\n"
                "  --max-speed V      m/s shown red with --color speed (default sqrt(2 |g| container height))\n"
                "  --width W, --height H   image size (default: the scene's render resolution)\n"
                "  --no-video         PNG frames only\n%s",
                kStageOptionsHelp);
    return 0;
  }
  ColourBy colourBy = ColourBy::Kind;
  if (auto c = args.option({"--color", "--colour"})) {
    if (*c == "kind") colourBy = ColourBy::Kind;
    else if (*c == "speed") colourBy = ColourBy::Speed;
    else args.fail("--color: expected kind or speed, got " + *c);
  }
  const std::optional<double> maxSpeedOption = args.doubleOption({"--max-speed"});
  if (maxSpeedOption && !(*maxSpeedOption > 0)) args.fail("--max-speed: must be > 0");
  const std::optional<int> width = args.intOption({"--width"}, 1, 16384);
  const std::optional<int> height = args.intOption({"--height"}, 1, 16384);
  const bool video = !args.flag({"--no-video"});
  const StageCommandOptions options = parseStageOptions(args, true);
  const std::vector<std::string> positional = args.positionals();
  if (positional.size() != 1) args.fail("expected one SCENE");
  const std::string& sceneFile = positional[0];

  const Scene scene = loadScene(sceneFile, {options.stage.force});
  const auto [first, last] = checkedFrameRange(args, scene, options.stage);
  const fs::path inFolder = options.stage.outDir / "particles";
  for (int f = first; f <= last; ++f) {
    const fs::path file = frameFile(inFolder, f, "vdb");
    if (!fs::exists(file))
      throw std::runtime_error(file.string() + ": missing; run `kurage sim` for these frames first");
  }
  const float containerHeight = (scene.sim.container.max - scene.sim.container.min).dot(-scene.sim.gravity.normalized());
  const float maxSpeed = maxSpeedOption ? float(*maxSpeedOption)
                                        : std::sqrt(2.0f * scene.sim.gravity.norm() * std::abs(containerHeight));
  render::PreviewSettings settings;
  settings.width = width.value_or(scene.render.settings.width);
  settings.height = height.value_or(scene.render.settings.height);
  // A fixed light from above, over the camera's shoulder, so the preview depends on the scene's
  // camera and resolution only.
  const render::Camera& camera = scene.render.camera;
  const Eigen::Vector3f down = scene.sim.gravity.squaredNorm() > 0 ? Eigen::Vector3f(scene.sim.gravity.normalized())
                                                                   : Eigen::Vector3f(0, 0, -1);
  settings.lightDirection = 2.0f * down + (camera.lookAt - camera.position).normalized();
  const float radius = 0.5f * scene.sim.fluid.spacing;

  ThreadLimit threads(options.threads);
  const ClaimedOutput claim(options.stage.outDir, "preview " + sceneFile);
  const fs::path outFolder = outputFolder(options.stage.outDir, "preview");
  render::PreviewRenderer renderer;
  Progress progress("preview", last - first + 1, options.stage.progress);
  double readSeconds = 0, drawSeconds = 0, writeSeconds = 0;
  for (int f = first; f <= last; ++f) {
    throwIfInterrupted();
    auto start = std::chrono::steady_clock::now();
    const ParticleFrame frame = readParticleFrame(frameFile(inFolder, f, "vdb"), {"sim", stageHash(scene, "sim"), f});
    render::PreviewSpheres spheres;
    spheres.centres.resize(frame.size());
    spheres.radii.assign(frame.size(), radius);
    spheres.colours.resize(frame.size());
    for (size_t i = 0; i < frame.size(); ++i) {
      spheres.centres[i] = Eigen::Vector3f(frame.px[i], frame.py[i], frame.pz[i]);
      if (colourBy == ColourBy::Kind) {
        spheres.colours[i] = kindColour(frame.kind[i]);
      } else {
        const float speed = Eigen::Vector3f(frame.vx[i], frame.vy[i], frame.vz[i]).norm();
        spheres.colours[i] = speedColour(speed / maxSpeed);
      }
    }
    auto next = std::chrono::steady_clock::now();
    readSeconds += std::chrono::duration<double>(next - start).count();
    start = next;
    const render::Image image = renderer.render(spheres, camera, settings);
    next = std::chrono::steady_clock::now();
    drawSeconds += std::chrono::duration<double>(next - start).count();
    start = next;
    writePng(image, frameFile(outFolder, f, "png"));
    writeSeconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    progress.advance(f - first + 1);
  }
  progress.finish();
  throwIfInterrupted();
  const int frames = last - first + 1;
  std::fprintf(stderr, "preview: %d frames, %.1f frames/s drawing (%s), %.1f frames/s with reading and PNG writing\n",
               frames, frames / drawSeconds, renderer.glVersion().c_str(),
               frames / (readSeconds + drawSeconds + writeSeconds));
  std::printf("preview: %s\n", outFolder.string().c_str());

  if (!video) return 0;
  encodeVideoInterruptibly(outFolder, first, frames, scene.output.fps, options.stage.outDir / "preview.mp4");
  return 0;
}

}  // namespace kurage::pipeline
