// kurage bench render: path tracer throughput on a fixed built-in scene at 1280x720.
//
// The scene: a metaball surface of 3,456 particles (a wavy 24 x 12 x 12 heap of water, meshed
// from its level set as the surface stage does), water material (dielectric, IOR 1.33, light
// absorption), checker ground, sun of 0.53 degrees and a sky gradient, seen at an angle; max
// depth 8. Reported for 1 and 2 threads: Mrays/s of camera rays and of all rays (camera, bounce
// and shadow rays, each an Embree query), and seconds per frame (scene build included).
#include "pipeline/cli.h"
#include "render/surfacing.h"
#include "render/tracer.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>

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

}  // namespace

int benchRender(ArgParser& args) {
  if (args.flag({"-h", "--help"})) {
    std::printf("usage: kurage bench render [--spp N] [--json]\n\n"
                "Renders a fixed scene (a metaball water heap over a checker ground, sun and sky) at 1280x720\n"
                "with N samples per pixel (default 4) and max depth 8 on 1 and 2 threads; prints Mrays/s\n"
                "(camera rays, all rays) and seconds per frame. --json prints one JSON object.\n");
    return 0;
  }
  const bool json = args.flag({"--json"});
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

  nlohmann::json result = {{"benchmark", "render"},
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
