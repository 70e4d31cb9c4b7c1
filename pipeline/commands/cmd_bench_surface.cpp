// kurage bench surface: surfacing throughput from particle caches to metaball level sets and
// meshes, with OpenVDB's ParticlesToLevelSet on the same particles for comparison.
//
// The particles are a "settled tank" made without simulating: a lattice block of spacing 1 m,
// twice as wide and long as it is deep (nx = ny = 2 nz), every particle moved by a small
// deterministic jitter of up to +-0.05 spacings per axis (a hash of its index), so the surface
// is flat with small ripples, like a fluid at rest, and every run sees the same particles.
// Metaball parameters: R = 2 spacings, T = 0.6, s = 1, voxel 0.5 spacings, half width 3.
//
// For each particle count and thread count: the block is written once as a particle cache
// (pipeline::writeParticleFrame, in a temporary folder), then each repetition times
//   read   readParticleFrame + the fluid positions
//   level set  render::buildMetaballLevelSet
//   mesh   render::meshLevelSet of that level set
//   vdb    render::buildParticleSpheresLevelSet (tools::ParticlesToLevelSet), sphere radius =
//          the radius of a single blob's surface, R sqrt(1 - sqrt(T/s)) = 0.95 m
//   clip   render::intersectWithBox of the level set with the tank [0, nx] x [0, ny] x [0, nz + 2]
//          grown by a quarter voxel, as the surface stage clips to the container (the particles
//          touch its walls and floor)
//   aniso  render::buildMetaballLevelSet with anisotropic kernels (render/anisotropy.h;
//          neighbourhood 1.5 R, smoothing 0.9, the settings of the flat-water test)
// and reports the fastest repetition of each.
#include "pipeline/commands/cli.h"
#include "pipeline/commands/machine.h"
#include "pipeline/io/particle_cache.h"
#include "render/particle_spheres.h"
#include "render/surfacing.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <unistd.h>

namespace kurage::pipeline {

namespace {

namespace fs = std::filesystem;

// Deterministic jitter in [-amplitude, amplitude] from a particle index and an axis.
float jitter(uint64_t index, uint64_t axis, float amplitude) {
  uint64_t x = index * 3 + axis + 0x9E3779B97F4A7C15ull;  // splitmix64
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  x ^= x >> 31;
  const double unit = double(x >> 11) * (1.0 / 9007199254740992.0);  // [0, 1)
  return float((2.0 * unit - 1.0) * amplitude);
}

// The tank's upper corner for settledTank(particles): walls at the lattice's outer faces, the
// top 2 m above the particles.
Eigen::Vector3f tankCorner(const ParticleFrame& frame) {
  Eigen::Vector3f hi = Eigen::Vector3f::Zero();
  for (size_t i = 0; i < frame.size(); ++i) hi = hi.cwiseMax(Eigen::Vector3f(frame.px[i], frame.py[i], frame.pz[i]));
  return Eigen::Vector3f(std::round(hi.x()), std::round(hi.y()), std::round(hi.z()) + 2.0f);
}

ParticleFrame settledTank(int particles) {
  const int nz = std::max(2, int(std::lround(std::cbrt(particles / 4.0))));
  const int nx = std::max(2, int(std::lround(std::sqrt(particles / double(nz)))));
  ParticleFrame frame;
  const size_t n = size_t(nx) * size_t(nx) * size_t(nz);
  for (auto* v : {&frame.px, &frame.py, &frame.pz, &frame.vx, &frame.vy, &frame.vz}) v->reserve(n);
  uint64_t index = 0;
  for (int i = 0; i < nx; ++i)
    for (int j = 0; j < nx; ++j)
      for (int k = 0; k < nz; ++k, ++index) {
        frame.px.push_back(0.5f + float(i) + jitter(index, 0, 0.05f));
        frame.py.push_back(0.5f + float(j) + jitter(index, 1, 0.05f));
        frame.pz.push_back(0.5f + float(k) + jitter(index, 2, 0.05f));
        frame.vx.push_back(0.0f);
        frame.vy.push_back(0.0f);
        frame.vz.push_back(0.0f);
        frame.id.push_back(int64_t(index));
        frame.kind.push_back(0);
      }
  return frame;
}

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

struct SurfaceRun {
  size_t particles = 0;
  int threads = 0;
  double readSeconds = 1e300, levelSetSeconds = 1e300, meshSeconds = 1e300, vdbSeconds = 1e300;
  double clipSeconds = 1e300, anisotropicSeconds = 1e300;
  size_t voxels = 0, bytes = 0, triangles = 0, vdbVoxels = 0, vdbBytes = 0;
};

SurfaceRun measure(const fs::path& cache, const render::MetaballParams& params, float sphereRadius,
                   const Eigen::Vector3f& tank, int threads, int repeats, bool withReference) {
  ThreadLimit limit(threads);
  SurfaceRun r;
  r.threads = threads;
  for (int rep = 0; rep < repeats; ++rep) {
    auto start = std::chrono::steady_clock::now();
    const ParticleFrame frame = readParticleFrame(cache);
    std::vector<Eigen::Vector3f> fluid;
    fluid.reserve(frame.size());
    for (size_t i = 0; i < frame.size(); ++i)
      if (frame.kind[i] == 0) fluid.emplace_back(frame.px[i], frame.py[i], frame.pz[i]);
    r.readSeconds = std::min(r.readSeconds, secondsSince(start));
    r.particles = fluid.size();

    start = std::chrono::steady_clock::now();
    const render::LevelSet levelSet = render::buildMetaballLevelSet(fluid, params);
    r.levelSetSeconds = std::min(r.levelSetSeconds, secondsSince(start));
    r.voxels = levelSet.activeVoxelCount();
    r.bytes = levelSet.memoryBytes();

    {
      render::LevelSet clipped = render::buildMetaballLevelSet(fluid, params);
      const Eigen::Vector3f margin = Eigen::Vector3f::Constant(0.25f * params.voxelSize);
      start = std::chrono::steady_clock::now();
      render::intersectWithBox(clipped, -margin, tank + margin);
      r.clipSeconds = std::min(r.clipSeconds, secondsSince(start));
    }
    {
      render::MetaballParams anisotropic = params;
      anisotropic.kernel = render::MetaballKernel::Anisotropic;
      anisotropic.anisotropy.neighbourRadius = 1.5f;
      anisotropic.anisotropy.smoothing = 0.9f;
      start = std::chrono::steady_clock::now();
      const render::LevelSet ellipsoids = render::buildMetaballLevelSet(fluid, anisotropic);
      r.anisotropicSeconds = std::min(r.anisotropicSeconds, secondsSince(start));
    }

    start = std::chrono::steady_clock::now();
    const render::TriangleMesh mesh = render::meshLevelSet(levelSet);
    r.meshSeconds = std::min(r.meshSeconds, secondsSince(start));
    r.triangles = mesh.triangles.size();

    if (withReference) {
      start = std::chrono::steady_clock::now();
      const render::LevelSet spheres =
          render::buildParticleSpheresLevelSet(fluid, sphereRadius, params.voxelSize, params.halfWidth);
      r.vdbSeconds = std::min(r.vdbSeconds, secondsSince(start));
      r.vdbVoxels = spheres.activeVoxelCount();
      r.vdbBytes = spheres.memoryBytes();
    }
  }
  return r;
}

// A fresh folder under the system temporary directory, removed at the end.
class ScratchDir {
public:
  ScratchDir() {
    path_ = fs::temp_directory_path() / ("kurage-bench-surface-" + std::to_string(::getpid()));
    fs::create_directories(path_);
  }
  ~ScratchDir() {
    std::error_code ignored;
    fs::remove_all(path_, ignored);
  }
  const fs::path& path() const { return path_; }

private:
  fs::path path_;
};

}  // namespace

int benchSurface(ArgParser& args) {
  if (args.flag({"-h", "--help"})) {
    std::printf(
        "usage: kurage bench surface [--particles N] [--threads N] [--repeat N] [--no-reference] [--json]\n\n"
        "Times particle caches -> metaball level sets -> meshes for a settled tank (a jittered lattice\n"
        "block, spacing 1, blob radius 2, threshold 0.6, voxel 0.5) of about 100000 and 1000000\n"
        "particles on 1 and 2 threads, and OpenVDB's ParticlesToLevelSet on the same particles\n"
        "(--no-reference skips it); also the clip to the tank's walls and the level set with anisotropic\n"
        "kernels (clip s, aniso s). Rates are particles per second; the fastest of --repeat runs\n"
        "(default 2) is reported. --particles and --threads pick one value each.\n");
    return 0;
  }
  const bool json = args.flag({"--json"});
  const bool withReference = !args.flag({"--no-reference"});
  const int repeats = args.intOption({"--repeat"}, 1, 1000).value_or(2);
  std::vector<int> counts{100000, 1000000};
  if (auto n = args.intOption({"--particles"}, 8, 100000000)) counts = {*n};
  std::vector<int> threadCounts{1, 2};
  if (auto t = args.intOption({"--threads"}, 1, 1024)) threadCounts = {*t};
  if (!args.positionals().empty()) args.fail("unexpected argument");

  render::MetaballParams params;
  params.radius = 2.0f;
  params.threshold = 0.6f;
  params.strength = 1.0f;
  params.voxelSize = 0.5f;
  params.halfWidth = 3.0f;
  const float sphereRadius =
      params.radius * std::sqrt(1.0f - std::sqrt(params.threshold / params.strength));

  nlohmann::json out = {
      {"benchmark", "surface"}, {"machine", machineRecord()},
      {"scene", "settled tank: lattice block nx = ny = 2 nz, spacing 1, jitter +-0.05 per axis"},
      {"metaball", {{"radius", params.radius}, {"threshold", params.threshold}, {"strength", params.strength},
                    {"voxel_size", params.voxelSize}, {"half_width", params.halfWidth}}},
      {"reference", "openvdb::tools::particlesToSdf, sphere radius " + std::to_string(sphereRadius)},
      {"repeats", repeats},
      {"runs", nlohmann::json::array()}};
  if (!json)
    std::printf("%9s %3s %7s %9s %9s %9s %10s %10s %9s %10s %7s %8s %8s %10s\n", "particles", "thr", "read s", "lset s",
                "Mp/s lset", "Mp/s +rd", "voxels", "MB", "mesh s", "Mp/s mesh", "clip s", "aniso s", "vdb s",
                "Mp/s vdb");
  const ScratchDir scratch;
  for (int count : counts) {
    const fs::path cache = scratch.path() / ("tank_" + std::to_string(count) + ".vdb");
    const ParticleFrame frame = settledTank(count);
    writeParticleFrame(cache, frame);
    const Eigen::Vector3f tank = tankCorner(frame);
    for (int threads : threadCounts) {
      const SurfaceRun r = measure(cache, params, sphereRadius, tank, threads, repeats, withReference);
      const double n = double(r.particles);
      nlohmann::json run = {
          {"particles", r.particles},
          {"threads", r.threads},
          {"read_seconds", r.readSeconds},
          {"level_set_seconds", r.levelSetSeconds},
          {"level_set_particles_per_s", n / r.levelSetSeconds},
          {"level_set_from_cache_particles_per_s", n / (r.readSeconds + r.levelSetSeconds)},
          {"level_set_active_voxels", r.voxels},
          {"level_set_bytes", r.bytes},
          {"mesh_seconds", r.meshSeconds},
          {"mesh_triangles", r.triangles},
          {"mesh_from_cache_particles_per_s", n / (r.readSeconds + r.levelSetSeconds + r.meshSeconds)},
          {"clip_to_container_seconds", r.clipSeconds},
          {"anisotropic_level_set_seconds", r.anisotropicSeconds}};
      if (withReference) {
        run["openvdb_seconds"] = r.vdbSeconds;
        run["openvdb_particles_per_s"] = n / r.vdbSeconds;
        run["openvdb_active_voxels"] = r.vdbVoxels;
        run["openvdb_bytes"] = r.vdbBytes;
      }
      out["runs"].push_back(run);
      if (!json) {
        std::printf("%9zu %3d %7.3f %9.3f %9.2f %9.2f %10zu %10.1f %9.3f %10.2f", r.particles, r.threads,
                    r.readSeconds, r.levelSetSeconds, n / r.levelSetSeconds / 1e6,
                    n / (r.readSeconds + r.levelSetSeconds) / 1e6, r.voxels, r.bytes / 1e6, r.meshSeconds,
                    n / (r.readSeconds + r.levelSetSeconds + r.meshSeconds) / 1e6);
        std::printf(" %7.3f %8.3f", r.clipSeconds, r.anisotropicSeconds);
        if (withReference)
          std::printf(" %8.3f %10.2f", r.vdbSeconds, n / r.vdbSeconds / 1e6);
        std::printf("\n");
        std::fflush(stdout);
      }
    }
  }
  if (json) std::printf("%s\n", out.dump(2).c_str());
  return 0;
}

}  // namespace kurage::pipeline
