// kurage bench render: path tracer throughput on a fixed built-in scene at 1280x720.
//
// The scene: a metaball surface of 3,456 particles (a wavy 24 x 12 x 12 heap of water, meshed
// from its level set as the surface stage does), water material (dielectric, IOR 1.33, light
// absorption), checker ground, sun of 0.53 degrees and a sky gradient, seen at an angle; max
// depth 8. Reported for 1 and 2 threads: Mrays/s of camera rays and of all rays (camera, bounce
// and shadow rays, each an Embree query), and seconds per frame (scene build included).
//
// With --rmse: image error against seconds for each integrator option, on the built-in scene or
// on a frame of a run (--scene, --from, --frame): RMSE (sRGB, 0..1, render/image.h imageRmse) against a
// reference rendered once by the path tracer with environment sampling and --reference-spp
// samples (another seed), and, for the whitted rows, also against whitted itself at 64 sub-pixel
// samples everywhere, the row's sky directions and its texture filtering (its only error is then
// aliasing; the "whitted unfiltered" rows point-sample checkers; the "whitted, adaptive" rows
// sample more only at edges, renderer.h's EdgeAdaptiveSettings). Every row but the
// whitted ones, the reference and --variance are path-traced whatever integrator the scene file
// names. With --variance: where the noise comes from, the
// RMSE between two renders that differ only in the seed, divided by sqrt(2) (the noise of one
// render), for each light alone and for each path depth.
#include "pipeline/commands/cli.h"
#include "pipeline/commands/machine.h"
#include "pipeline/io/exr.h"
#include "pipeline/io/image_file.h"
#include "pipeline/io/surface_file.h"
#include "pipeline/io/particle_cache.h"
#include "pipeline/render_scene.h"
#include "pipeline/stages.h"
#include "render/image.h"
#include "render/surfacing.h"
#include "render/renderer.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

namespace kurage::pipeline {

namespace {

render::TriangleMesh benchMesh() {
  std::vector<Eigen::Vector3f> particles;
  for (int i = 0; i < 24; ++i)
    for (int j = 0; j < 12; ++j)
      for (int k = 0; k < 12; ++k) {
        const float x = float(i), y = float(j);
        const float top = 6.0f + 3.0f * std::sin(0.5f * x) * std::cos(0.6f * y);  // a wavy heap
        if (float(k) > top) continue;
        particles.emplace_back(x + 0.5f, y + 0.5f, float(k) + 0.5f);
      }
  render::MetaballParams blob;
  blob.radius = 2.0f;
  blob.threshold = 0.5f;
  blob.voxelSize = 0.25f;
  return render::meshLevelSet(render::buildMetaballLevelSet(particles, blob));
}

// What one frame needs: the scene (for its render settings) and a function that renders it.
struct BenchFrame {
  Scene scene;
  std::function<render::Image(const Scene&, render::RenderStats*)> render;
};

struct BenchRow {
  std::string label;
  std::function<void(render::RenderSettings&)> set;
};

std::vector<BenchRow> rmseRows() {
  using S = render::RenderSettings;
  std::vector<BenchRow> rows;
  for (int spp : {1, 4, 16, 64})
    rows.push_back({"before: sky by BSDF, no split, " + std::to_string(spp) + " spp", [spp](S& s) {
                      s.environmentSampling = false;
                      s.fresnelSplitting = false;
                      s.samplesPerPixel = spp;
                    }});
  for (int spp : {1, 4, 16, 64})
    rows.push_back({"path (default: sky MIS, split), " + std::to_string(spp) + " spp", [spp](S& s) { s.samplesPerPixel = spp; }});
  for (int spp : {1, 3, 4, 5, 6, 8, 10, 12, 16})
    rows.push_back({"path + denoiser, " + std::to_string(spp) + " spp", [spp](S& s) {
                      s.samplesPerPixel = spp;
                      s.denoise.enabled = true;
                    }});
  for (const auto& [error, lo, hi] : {std::tuple{0.1f, 4, 64}, std::tuple{0.05f, 8, 256}})
    rows.push_back({"path, adaptive " + std::to_string(error).substr(0, 4) + " (" + std::to_string(lo) + "-" +
                        std::to_string(hi) + " spp)",
                    [error, lo, hi](S& s) {
                      s.adaptive.enabled = true;
                      s.adaptive.relativeError = error;
                      s.adaptive.minSamples = lo;
                      s.adaptive.maxSamples = hi;
                    }});
  for (const bool filter : {true, false})
    for (const auto& [spp, sky] : {std::pair{1, 4}, std::pair{2, 4}, std::pair{4, 4}, std::pair{6, 4}, std::pair{8, 4},
                                   std::pair{16, 4}, std::pair{8, 2}, std::pair{1, 16}, std::pair{4, 16}})
      rows.push_back({std::string(filter ? "whitted, " : "whitted unfiltered, ") + std::to_string(spp) + " spp, " +
                          std::to_string(sky) + " sky rays",
                      [spp, sky, filter](S& s) {
                        s.integrator = render::IntegratorType::Whitted;
                        s.samplesPerPixel = spp;
                        s.whitted.skyDirections = sky;
                        s.whitted.filterTextures = filter;
                        s.whitted.adaptive.enabled = false;
                        s.whitted.skyFilter.enabled = false;
                      }});
  for (const auto& [spp, sky, tile] : {std::tuple{3, 4, 3}, std::tuple{4, 2, 3}, std::tuple{4, 3, 3}, std::tuple{4, 4, 3},
                                       std::tuple{3, 4, 5}, std::tuple{4, 2, 5}, std::tuple{4, 3, 5}, std::tuple{4, 4, 4},
                                       std::tuple{4, 2, 4}, std::tuple{6, 2, 3}})
    rows.push_back({"whitted, sky filter " + std::to_string(tile) + "x" + std::to_string(tile) + ", " +
                        std::to_string(spp) + " spp, " + std::to_string(sky) + " sky rays",
                    [spp, sky, tile](S& s) {
                      s.integrator = render::IntegratorType::Whitted;
                      s.samplesPerPixel = spp;
                      s.whitted.skyDirections = sky;
                      s.whitted.adaptive.enabled = false;
                      s.whitted.skyFilter.enabled = true;
                      s.whitted.skyFilter.tile = tile;
                    }});
  for (const auto& [threshold, lo, hi] : {std::tuple{0.02f, 1, 16}, std::tuple{0.04f, 1, 16}, std::tuple{0.02f, 2, 16},
                                          std::tuple{0.04f, 2, 16}, std::tuple{0.08f, 2, 16}, std::tuple{0.02f, 2, 8},
                                          std::tuple{0.04f, 2, 32}, std::tuple{0.01f, 2, 16}, std::tuple{0.01f, 4, 16},
                                          std::tuple{0.02f, 4, 16}, std::tuple{0.04f, 4, 16}, std::tuple{0.02f, 4, 32}})
    rows.push_back({"whitted, adaptive " + std::to_string(threshold).substr(0, 4) + ", " + std::to_string(lo) + "-" +
                        std::to_string(hi) + " spp, 4 sky rays",
                    [threshold, lo, hi](S& s) {
                      s.integrator = render::IntegratorType::Whitted;
                      s.samplesPerPixel = hi;
                      s.whitted.skyDirections = 4;
                      s.whitted.adaptive = {true, threshold, lo};
                      s.whitted.skyFilter.enabled = false;
                    }});
  return rows;
}

// The frame's scene with the path tracer, whatever integrator the scene file names (the rows and
// the reference are path-traced unless a row says whitted).
Scene pathTraced(const Scene& scene) {
  Scene s = scene;
  s.render.settings.integrator = render::IntegratorType::Path;
  return s;
}

// The path tracer's converged frame: read from `file` when it exists (and has the frame's size),
// else rendered with `spp` samples (another seed) and, with a file named, written there.
render::Image rmseReference(const BenchFrame& frame, const std::optional<std::string>& file, int spp,
                            render::RenderStats& stats, bool& read) {
  const render::RenderSettings& base = frame.scene.render.settings;
  read = file && std::filesystem::exists(*file);
  if (read) {
    render::Image image = readExr(*file).beauty;
    if (image.width() != base.width || image.height() != base.height)
      throw std::runtime_error(*file + ": the reference is " + std::to_string(image.width()) + "x" +
                               std::to_string(image.height()) + ", the frame " + std::to_string(base.width) + "x" +
                               std::to_string(base.height));
    return image;
  }
  Scene scene = pathTraced(frame.scene);
  scene.render.settings.samplesPerPixel = spp;
  scene.render.settings.seed = base.seed + 1;
  render::Image image = frame.render(scene, &stats);
  if (file) writeExr(*file, image, nullptr, 0.0, 0);
  return image;
}

// Writes a row's image and its camera samples per pixel (grey: the most samples white) to `dir`,
// named by the row's label.
void writeRowImages(const std::filesystem::path& dir, const std::string& label, const render::Image& image,
                    const render::RenderStats& stats) {
  std::string name;
  for (const char c : label) name += std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
  std::filesystem::create_directories(dir);
  writePng(image, dir / (name + ".png"));
  if (stats.pixelSamples.size() != size_t(image.width()) * size_t(image.height())) return;
  render::Image samples(image.width(), image.height());
  const uint32_t most = std::max<uint32_t>(1, *std::max_element(stats.pixelSamples.begin(), stats.pixelSamples.end()));
  for (int y = 0; y < image.height(); ++y)
    for (int x = 0; x < image.width(); ++x) {
      // linear grey, so that the PNG's sRGB encoding shows samples / most
      const float v = render::srgbToLinear(float(stats.pixelSamples[size_t(y) * size_t(image.width()) + size_t(x)]) /
                                           float(most));
      samples.at(x, y) = {v, v, v, 1.0f};
    }
  writePng(samples, dir / (name + "-samples.png"));
}

// Whether `label` contains one of the |-separated parts of `only`.
bool labelMatches(const std::string& label, const std::string& only) {
  for (size_t start = 0;;) {
    const size_t end = only.find('|', start);
    if (label.find(only.substr(start, end - start)) != std::string::npos) return true;
    if (end == std::string::npos) return false;
    start = end + 1;
  }
}

int benchRmse(const BenchFrame& frame, int threads, int referenceSpp, const std::optional<std::string>& referenceFile,
              const std::optional<std::string>& only, int repeat, const std::optional<std::string>& images, bool json) {
  ThreadLimit limit(threads);
  const Scene pathScene = pathTraced(frame.scene);
  render::RenderStats referenceStats;
  bool referenceRead = false;
  const render::Image reference = rmseReference(frame, referenceFile, referenceSpp, referenceStats, referenceRead);
  // Whitted's own converged frame, per number of sky directions and texture filtering: 64
  // sub-pixel samples.
  std::map<std::pair<int, bool>, render::Image> whittedReferences;
  const auto whittedReference = [&](const render::WhittedSettings& whitted) -> const render::Image& {
    const std::pair key{whitted.skyDirections, whitted.filterTextures};
    auto it = whittedReferences.find(key);
    if (it != whittedReferences.end()) return it->second;
    Scene whittedScene = pathScene;
    whittedScene.render.settings.integrator = render::IntegratorType::Whitted;
    whittedScene.render.settings.whitted = whitted;
    whittedScene.render.settings.samplesPerPixel = 64;
    whittedScene.render.settings.whitted.adaptive.enabled = false;
    whittedScene.render.settings.whitted.skyFilter.enabled = false;
    return whittedReferences.emplace(key, frame.render(whittedScene, nullptr)).first->second;
  };
  const render::RenderSettings& base = frame.scene.render.settings;
  nlohmann::json result = {{"benchmark", "render_rmse"}, {"machine", machineRecord()},
                           {"width", base.width}, {"height", base.height},
                           {"threads", threads}, {"repeat", repeat}, {"reference_spp", referenceRead ? nlohmann::json(nullptr) : nlohmann::json(referenceSpp)},
                           {"reference_file", referenceFile ? nlohmann::json(*referenceFile) : nlohmann::json(nullptr)},
                           {"reference_seconds", referenceStats.seconds}, {"rows", nlohmann::json::array()}};
  if (!json) {
    std::printf("bench render --rmse: %dx%d, %d threads, max depth %d; reference: ", base.width, base.height, threads,
                base.maxDepth);
    if (referenceRead) std::printf("%s (read)\n", referenceFile->c_str());
    else std::printf("default path tracer, %d spp (%.1f s)\n", referenceSpp, referenceStats.seconds);
    std::printf("  %-44s %9s %8s %9s %s\n", "run", "s/frame", "RMSE", "mean spp", "RMSE vs whitted@64");
  }
  for (const BenchRow& row : rmseRows()) {
    if (only && !labelMatches(row.label, *only)) continue;
    Scene scene = pathScene;
    row.set(scene.render.settings);
    render::RenderStats stats;
    const render::Image image = frame.render(scene, &stats);
    // Renders are deterministic: repeats change only the seconds, of which the median is kept.
    std::vector<double> seconds{stats.seconds};
    for (int k = 1; k < repeat; ++k) {
      render::RenderStats again;
      frame.render(scene, &again);
      seconds.push_back(again.seconds);
    }
    std::sort(seconds.begin(), seconds.end());
    stats.seconds = seconds[seconds.size() / 2];
    const double rmse = render::imageRmse(image, reference);
    const bool whitted = scene.render.settings.integrator == render::IntegratorType::Whitted;
    const double self = whitted ? render::imageRmse(image, whittedReference(scene.render.settings.whitted)) : -1.0;
    const double spp = double(stats.samples) / (double(base.width) * base.height);
    if (images) writeRowImages(*images, row.label, image, stats);
    result["rows"].push_back({{"run", row.label}, {"seconds", stats.seconds}, {"rmse", rmse}, {"mean_spp", spp},
                              {"rmse_vs_whitted64", whitted ? nlohmann::json(self) : nlohmann::json(nullptr)}});
    if (!json) {
      std::printf("  %-44s %9.3f %8.4f %9.1f", row.label.c_str(), stats.seconds, rmse, spp);
      if (whitted) std::printf(" %8.4f", self);
      std::printf("\n");
    }
  }
  if (json) std::printf("%s\n", result.dump(2).c_str());
  return 0;
}

// The noise of one render, by light and by depth: RMSE between seeds 0 and 1, / sqrt(2).
int benchVariance(const BenchFrame& frame, int threads, bool json) {
  const int spp = frame.scene.render.settings.samplesPerPixel;
  ThreadLimit limit(threads);
  const auto noise = [&](const std::function<void(Scene&)>& set) {
    Scene scene = pathTraced(frame.scene);
    set(scene);
    const render::Image a = frame.render(scene, nullptr);
    scene.render.settings.seed += 1;
    const render::Image b = frame.render(scene, nullptr);
    return render::imageRmse(a, b) / std::sqrt(2.0);
  };
  const auto noSun = [](Scene& s) { s.render.sun.irradiance.setZero(); };
  const auto noSky = [](Scene& s) {
    s.render.environment.type = render::EnvironmentType::Uniform;
    s.render.environment.zenith.setZero();
  };
  const auto noArea = [](Scene& s) { s.render.areaLights.clear(); };
  nlohmann::json result = {{"benchmark", "render_variance"}, {"machine", machineRecord()}, {"spp", spp},
                           {"rows", nlohmann::json::array()}};
  if (!json) std::printf("bench render --variance: noise (RMSE, sRGB) of one %d-spp render\n", spp);
  // before (sky by BSDF, no splitting), the sky sampled alone, the default (sky sampled, split)
  for (const auto& [sampled, split] : {std::pair{false, false}, std::pair{true, false}, std::pair{true, true}}) {
    const auto with = [&, sampled = sampled, split = split](const std::function<void(Scene&)>& f) {
      return [sampled, split, f](Scene& s) {
        s.render.settings.environmentSampling = sampled;
        s.render.settings.fresnelSplitting = split;
        f(s);
      };
    };
    const std::vector<std::pair<std::string, std::function<void(Scene&)>>> cases{
        {"all lights", with([](Scene&) {})},
        {"sun only", with([&](Scene& s) { noSky(s), noArea(s); })},
        {"sky only", with([&](Scene& s) { noSun(s), noArea(s); })},
        {"area lights only", with([&](Scene& s) { noSun(s), noSky(s); })},
        {"max depth 1", with([](Scene& s) { s.render.settings.maxDepth = 1; })},
        {"max depth 2", with([](Scene& s) { s.render.settings.maxDepth = 2; })},
        {"max depth 3", with([](Scene& s) { s.render.settings.maxDepth = 3; })},
        {"max depth 4", with([](Scene& s) { s.render.settings.maxDepth = 4; })},
        {"max depth 6", with([](Scene& s) { s.render.settings.maxDepth = 6; })},
    };
    for (const auto& [label, set] : cases) {
      const double n = noise(set);
      const std::string name =
          std::string(!sampled ? "before (sky BSDF): " : split ? "default (MIS, split): " : "sky MIS, no split: ") + label;
      result["rows"].push_back({{"case", name}, {"noise_rmse", n}});
      if (!json) std::printf("  %-44s %8.4f\n", name.c_str(), n);
    }
  }
  if (json) std::printf("%s\n", result.dump(2).c_str());
  return 0;
}

}  // namespace

int benchRender(ArgParser& args) {
  if (args.flag({"-h", "--help"})) {
    std::printf("usage: kurage bench render [--spp N] [--json]\n"
                "       kurage bench render --rmse|--variance [--scene SCENE --from OUT --frame F [--quality Q]]\n"
                "                           [--width W --height H --spp N --reference-spp R --threads T] [--json]\n"
                "                           [--reference FILE.exr] [--rows TEXT] [--repeat N] [--images DIR]\n\n"
                "Renders a fixed scene (a metaball water heap over a checker ground, sun and sky) at 1280x720\n"
                "with N samples per pixel (default 4) and max depth 8 on 1 and 2 threads; prints Mrays/s\n"
                "(camera rays, all rays) and seconds per frame. --json prints one JSON object.\n\n"
                "--rmse: seconds and RMSE (sRGB, 0..1) of each integrator option (path as it was: sky by BSDF\n"
                "sampling only, no Fresnel splitting; the default; with the denoiser; adaptive; whitted) against a\n"
                "reference (the default path tracer, R spp, default 1024, another seed), on the fixed scene at 480x270 or on frame F of a\n"
                "run (OUT/surfaces, and OUT/particles for chains) at the scene's resolution; T threads (default 2).\n"
                "--reference FILE.exr: read the reference from FILE (its size must be the frame's), or render it\n"
                "and write it there when FILE does not exist (render a 4096-spp reference once, reuse it).\n"
                "--rows TEXT: only the rows whose label contains TEXT (e.g. \"denoiser\", \"whitted\"), or one of\n"
                "TEXT's |-separated parts (\"whitted, 4 spp, 4|whitted, 8 spp, 4\").\n"
                "--repeat N: render each row N times and report the median seconds (default 1).\n"
                "--images DIR: write each row's image and a map of its samples per pixel (grey, the most white)\n"
                "to DIR/LABEL.png and DIR/LABEL-samples.png.\n"
                "--variance: the noise of one N-spp render (default 4) by light and by path depth.\n");
    return 0;
  }
  const bool json = args.flag({"--json"});
  const bool rmse = args.flag({"--rmse"});
  const bool variance = args.flag({"--variance"});
  if (rmse || variance) {
    const auto sceneFile = args.option({"--scene"});
    const auto from = args.option({"--from"});
    const int frameIndex = args.intOption({"--frame"}, 0, 1000000).value_or(0);
    const auto quality = args.option({"--quality"});
    const auto width = args.intOption({"--width"}, 1, 16384);
    const auto height = args.intOption({"--height"}, 1, 16384);
    const auto sppOption = args.intOption({"--spp"}, 1, 65536);
    const int referenceSpp = args.intOption({"--reference-spp"}, 1, 1 << 20).value_or(1024);
    const int threads = args.intOption({"--threads"}, 1, 1024).value_or(2);
    const auto referenceFile = args.option({"--reference"});
    const auto only = args.option({"--rows"});
    const int repeat = args.intOption({"--repeat"}, 1, 100).value_or(1);
    const auto images = args.option({"--images"});
    if (!args.positionals().empty()) args.fail("takes no positional arguments");
    if (sceneFile.has_value() != from.has_value()) args.fail("--scene and --from go together");
    BenchFrame frame;
    std::shared_ptr<render::TriangleMesh> mesh;
    std::map<std::string, render::LevelSet> surfaces;
    std::vector<render::CurveSet> curves;
    double time = 0.0;
    if (sceneFile) {
      frame.scene = loadScene(*sceneFile);
      if (quality && *quality == "preview") applyQuality(frame.scene, Quality::Preview);
      else if (quality && *quality != "final") args.fail("--quality must be preview or final");
      const std::filesystem::path out(*from);
      char name[32];
      std::snprintf(name, sizeof name, "%04d.vdb", frameIndex);
      surfaces = readSurfaceFile(out / "surfaces" / name);
      if (hasChains(frame.scene)) curves.push_back(chainTubes(frame.scene, readParticleFrame(out / "particles" / name)));
      time = frame.scene.output.frameTime(frameIndex);
      frame.render = [&](const Scene& s, render::RenderStats* stats) { return renderSurfaces(s, surfaces, time, stats, curves); };
    } else {
      mesh = std::make_shared<render::TriangleMesh>(benchMesh());
      render::RenderSettings& r = frame.scene.render.settings;
      r.width = 480;
      r.height = 270;
      r.maxDepth = 8;
      frame.scene.render.camera.position = {12, -26, 16};
      frame.scene.render.camera.lookAt = {12, 6, 3};
      frame.scene.render.camera.verticalFovDegrees = 40.0f;
      frame.scene.render.sun.direction = {-0.5f, 0.6f, -1.0f};
      frame.scene.render.ground.checkerSize = 2.0f;
      frame.render = [&](const Scene& s, render::RenderStats* stats) {
        render::RenderScene scene;
        scene.meshes.push_back({mesh.get(), s.render.fluidMaterial});
        scene.camera = s.render.camera;
        scene.sun = s.render.sun;
        scene.ground = s.render.ground;
        scene.environment.type = s.render.environment.type;
        scene.environment.zenith = s.render.environment.zenith;
        scene.environment.horizon = s.render.environment.horizon;
        scene.rectLights = s.render.areaLights;
        return render::renderFrame(scene, s.render.settings, stats);
      };
    }
    if (width) frame.scene.render.settings.width = *width;
    if (height) frame.scene.render.settings.height = *height;
    frame.scene.render.settings.samplesPerPixel = sppOption.value_or(4);
    return rmse ? benchRmse(frame, threads, referenceSpp, referenceFile, only, repeat, images, json) : benchVariance(frame, threads, json);
  }
  const int spp = args.intOption({"--spp"}, 1, 4096).value_or(4);
  if (!args.positionals().empty()) args.fail("takes no positional arguments");

  const render::TriangleMesh mesh = benchMesh();
  render::RenderScene scene;
  render::Material water;
  water.type = render::MaterialType::Dielectric;
  water.ior = 1.33f;
  water.absorption = {0.12f, 0.04f, 0.02f};
  scene.meshes.push_back({&mesh, water});
  scene.camera.position = {12, -26, 16};
  scene.camera.lookAt = {12, 6, 3};
  scene.camera.verticalFovDegrees = 40.0f;
  scene.sun.direction = {-0.5f, 0.6f, -1.0f};
  scene.ground.checkerSize = 2.0f;
  render::RenderSettings settings;
  settings.width = 1280;
  settings.height = 720;
  settings.samplesPerPixel = spp;
  settings.maxDepth = 8;

  nlohmann::json result = {{"benchmark", "render"}, {"machine", machineRecord()},
                           {"width", settings.width},
                           {"height", settings.height},
                           {"spp", spp},
                           {"max_depth", settings.maxDepth},
                           {"triangles", mesh.triangles.size()},
                           {"runs", nlohmann::json::array()}};
  if (!json)
    std::printf("bench render: %dx%d, %d spp, max depth 8, metaball water heap (%zu triangles) + ground, sun, sky\n",
                settings.width, settings.height, spp, mesh.triangles.size());
  for (int threads : {1, 2}) {
    ThreadLimit limit(threads);
    render::RenderStats stats;
    render::renderFrame(scene, settings, &stats);
    const double primary = double(stats.primaryRays) / stats.seconds * 1e-6;
    const double total = double(stats.totalRays) / stats.seconds * 1e-6;
    result["runs"].push_back({{"threads", threads},
                              {"seconds_per_frame", stats.seconds},
                              {"primary_rays", stats.primaryRays},
                              {"total_rays", stats.totalRays},
                              {"primary_mrays_per_s", primary},
                              {"total_mrays_per_s", total}});
    if (!json)
      std::printf("  %d thread%s: %7.2f s/frame  %6.2f Mrays/s primary  %6.2f Mrays/s total (%.2f rays per path)\n",
                  threads, threads == 1 ? " " : "s", stats.seconds, primary, total,
                  double(stats.totalRays) / double(stats.primaryRays));
  }
  if (json) std::printf("%s\n", result.dump(2).c_str());
  return 0;
}

}  // namespace kurage::pipeline
