// A scene: everything a run needs, loaded strictly from a JSON file. Each component is a typed
// parameter struct (sim/, render/ or below); pipeline/scene_params.h is the single registry of
// their JSON keys, units, defaults and valid ranges, from which the loader, run.json and
// scenes/schema.json are all derived.
#pragma once

#include "pipeline/param_visitor.h"
#include "render/airborne.h"
#include "render/surfacing.h"
#include "render/renderer.h"
#include "sim/params.h"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>
#include <vector>

namespace kurage::pipeline {

// Which exports the run makes after its surfaces (pipeline/exports.h says what each is).
struct ExportSelection {
  bool meshPly = false, meshObj = false, particlesVtp = false, particlesPly = false, chainsVtp = false,
       chainsObj = false;
  bool any() const { return meshPly || meshObj || particlesVtp || particlesPly || chainsVtp || chainsObj; }
  bool needsSurfaces() const { return meshPly || meshObj; }
};

struct OutputParams {
  float duration = 4.0f;  // s of simulated time
  float fps = 24.0f;      // frames per second; frame f is at time f / fps, f = 0 .. frameCount()-1
  ExportSelection exports;

  int frameCount() const;
  double frameTime(int frame) const { return frame / double(fps); }
};

struct SurfaceParams {
  render::MetaballParams fluid;
  render::AirborneParams airborne;  // smaller blobs for the fluid's jets and spray
  // Every body except chains becomes its own level set (grid named after the body). Bodies have
  // half the fluid's spacing, hence the finer default field.
  render::MetaballParams bodies = [] {
    render::MetaballParams m;
    m.radius = 1.0f;
    m.threshold = 0.5f;
    m.voxelSize = 0.125f;
    return m;
  }();
  // Every surface is intersected with the container (render::intersectWithBox), grown by a
  // quarter of the grid's voxel so that the floor and the walls, drawn at the container's faces,
  // stay in front of the water's own faces instead of coinciding with them; a body's by a
  // quarter of its voxel more than the fluid's, so that where a body lies against a wall with
  // the fluid behind it (a membrane pressed on the tank by the water it holds), its face is the
  // outer one and the fluid's blobs, wider than the sheet is thick, do not show through it.
  bool clipToContainer = true;
};

// The environment as the scene file gives it (render::Environment holds the decoded image).
struct EnvironmentParams {
  render::EnvironmentType type = render::EnvironmentType::Gradient;
  Eigen::Vector3f zenith{0.35f, 0.55f, 0.9f};
  Eigen::Vector3f horizon{0.85f, 0.9f, 0.95f};
  std::string image;  // equirectangular PNG, relative to the working directory
  float intensity = 1.0f;
  float rotation = 0.0f;  // degrees about z
};

// Particles drawn as spheres instead of surfaces (figures that explain the method).
enum class ParticleColouring { Kind, Speed, RestDensityFactor };
struct ParticleDisplayParams {
  bool spheres = false;
  float radius = 0.0f;  // metres; 0 = 0.4 fluid spacings
  ParticleColouring colourBy = ParticleColouring::Kind;
  float rangeMin = 0.0f;  // the value mapped to the start of the colour ramp (speed, factor)
  float rangeMax = 0.0f;  // ... and to its end; max <= min picks the frame's own range
};

// The container's walls drawn as a tank: the walls the camera looks at from inside (never the
// ones between the camera and the fluid), open at the top; the floor is the ground.
struct TankParams {
  bool enabled = false;
  float height = 0.0f;  // metres above container.min.z; 0 = the container's height
  render::Material material = [] {
    render::Material m;
    m.albedo = {0.7f, 0.7f, 0.68f};
    m.albedoB = {0.45f, 0.45f, 0.43f};
    m.checkerSize = 2.0f;
    return m;
  }();
};

// The emitters drawn as faucets (pipeline/render_scene.h, faucetTubes): a pipe of 1.2 times the
// nozzle's radius that ends at the nozzle, along its direction, and rises to above the tank.
struct FaucetParams {
  bool enabled = false;
  render::Material material = [] {
    render::Material m;
    m.type = render::MaterialType::Mirror;
    m.albedo = {0.55f, 0.55f, 0.57f};
    return m;
  }();
};

// The tubes drawn along chain bodies (oral arms): radius linear in the particle index, from the
// chain's first particle (where it hangs) to its last.
struct ChainRadiusParams {
  float root = 0.3f;  // metres
  float tip = 0.08f;  // metres
};

// The files the render stage writes per frame (render.outputs).
struct FrameOutputs {
  bool png = true;   // OUT/frames/NNNN.png (sRGB; the video is made from these)
  bool exr = false;  // OUT/frames/NNNN.exr (linear, with layers: pipeline/io/exr.h)
};

struct RenderParams {
  render::RenderSettings settings;  // resolution, samples, depth, seed, alpha (flat in the JSON)
  int bitDepth = 8;                 // PNG bits per channel, 8 or 16
  FrameOutputs outputs;
  render::Camera camera;
  std::vector<render::CameraKey> cameraKeys;
  render::SunLight sun;
  std::vector<render::RectLight> areaLights;
  EnvironmentParams environment;
  render::Ground ground;
  render::Material fluidMaterial = [] {
    render::Material m;
    m.type = render::MaterialType::Dielectric;
    m.albedo = {0.25f, 0.45f, 0.85f};
    m.ior = 1.33f;
    m.absorption = {0.12f, 0.04f, 0.02f};
    return m;
  }();
  render::Material bodyMaterial = [] {
    render::Material m;
    m.type = render::MaterialType::Translucent;
    m.albedo = {0.95f, 0.55f, 0.75f};
    m.ior = 1.35f;
    m.absorption = {0.05f, 0.4f, 0.2f};
    return m;
  }();
  render::Material chainMaterial = [] {  // the body material, more orange
    render::Material m;
    m.type = render::MaterialType::Translucent;
    m.albedo = {0.97f, 0.6f, 0.5f};
    m.ior = 1.35f;
    m.absorption = {0.05f, 0.35f, 0.4f};
    return m;
  }();
  ChainRadiusParams chainRadius;
  TankParams tank;
  FaucetParams faucets;
  render::ClipPlane clip;
  ParticleDisplayParams particles;
};

// What `--quality preview` changes (pipeline::applyQuality): a quick look at the whole animation
// before the final render. 0 derives the value from the scene's final settings.
struct PreviewQuality {
  int width = 0;            // px; 0 = half the render width
  int height = 0;           // px; 0 = half the render height
  int samples = 0;          // 0 = a quarter of the render samples, at least 1
  int maxDepth = 0;         // 0 = the render's max_depth, at most 6
  float voxelScale = 2.0f;  // surface voxel sizes (fluid and bodies) times this
  float fps = 0.0f;         // frames per second of the whole run (sim included); 0 = output.fps
};

enum class Quality { Final, Preview };

struct Scene {
  std::string name = "scene";
  std::string description;
  sim::SimParams sim;
  OutputParams output;
  SurfaceParams surface;
  RenderParams render;
  PreviewQuality previewQuality;
};

// Final leaves the scene as it is; Preview applies scene.previewQuality to the render settings and
// the surface voxel sizes.
void applyQuality(Scene& scene, Quality quality);

// What a scene costs, estimated from its parameters before anything is allocated.
struct SceneEstimate {
  double particles = 0;     // initial fluid particles (the fluid blocks; bodies and emitters not counted)
  double gridCells = 0;     // neighbour grid cells over the container (edge = the support radius)
  double frames = 0;        // output frames
  double memoryBytes = 0;   // particles x kBytesPerParticle + cells x 12 B + springs x 32 B
  // Bodies, from their shapes' extents before any is built (upper bounds): particles, and springs
  // (each particle joined to those within its connection radius), and the body with most springs.
  double bodyParticles = 0;
  double springs = 0;
  size_t mostSpringsBody = 0;
  // Time steps over output.duration (estimateSteps).
  double steps = 0;
  // The surface stage, per frame: the 8^3-voxel leaves of the metaball fields (fluid and bodies)
  // and their memory. An upper bound: the fewer of the leaves over the container grown by the
  // field radius and the leaves each particle's blob can reach (the container's, with an emitter).
  // A body with telescopic density counts at its blobs' largest radius, kMaxRadiusScale R
  // (render::stretchRadiusScales: a stretched particle's blob keeps the volume it stands for).
  double surfaceLeaves = 0;
  double surfaceBytes = 0;  // surfaceLeaves x kBytesPerSurfaceLeaf
  // The render stage, per frame: its image buffers, width x height x kBytesPerPixel, and its
  // meshes and their BVH, at most kBytesPerSurfaceLeaf x surfaceLeaves again.
  double renderBytes = 0;
};
inline constexpr double kBytesPerParticle = 600.0;  // simulation arrays and neighbour lists
// The surface stage's peak memory per leaf of the field: the summed field (2 KB), the level
// set's leaf and its distances, the container clip (measured: docs/design/reliability.md).
inline constexpr double kBytesPerSurfaceLeaf = 12e3;
// A frame's buffers per pixel: the image, the EXR layers and the denoiser's inputs.
inline constexpr double kBytesPerPixel = 64.0;
SceneEstimate estimateScene(const Scene& scene);
// Time steps to simulate `seconds` from t = 0: seconds / time_step.fixed_step, or, adaptive, the
// fewest it can take, seconds / time_step.max_step (a run whose step falls toward min_step takes
// more; SIGINT/SIGTERM stop it).
double estimateSteps(const Scene& scene, double seconds);

// The limits a scene must stay within (docs/design/reliability.md); `force` lifts the soft ones.
struct LoadOptions {
  bool force = false;
};
inline constexpr double kMaxParticles = 50e6;   // soft
inline constexpr double kMaxFrames = 100000;    // soft (about 70 minutes at 24 fps)
inline constexpr double kMaxFramesHard = 1e7;   // even with --force
inline constexpr double kMaxGridCells = 4e8;    // hard: the neighbour grid's own limit
inline constexpr double kMaxSprings = 2e7;      // soft (about 10 s and 1 GB to build)
inline constexpr double kMaxSteps = 1e7;        // soft (hours for a small scene, days for a large one)
// soft: the simulation's, the surface stage's or the render stage's memory above the machine's
// physical memory

// Refuses a scene above the limits with the estimate (SceneError naming the key that sets it), as
// loadScene does; for a scene changed after loading (--quality, --width, ...).
void checkSceneLimits(const Scene& scene, const std::string& file, const LoadOptions& options = {});

// Loads and validates a scene. Throws SceneError (file + JSON path) on any problem: unreadable
// file, JSON syntax or duplicate keys, unknown keys, wrong types, missing required values,
// out-of-range values (numbers beyond a 32-bit float too), inconsistencies between components
// (a fluid block outside the container, ...), a `name` that is not a plain file name, and a
// scene above the limits (the message gives the estimate).
Scene loadScene(const std::filesystem::path& file, const LoadOptions& options = {});
// Parses JSON text strictly: duplicate keys and numbers beyond a double are refused. Throws
// SceneError naming the file (and the line and column of a syntax error, the path of a duplicate).
nlohmann::json parseStrictJson(const std::string& text, const std::string& file);

// Same, from an already parsed document; `file` is only used in messages.
Scene parseScene(const nlohmann::json& document, const std::string& file, const LoadOptions& options = {});

// The parameters in effect (after defaults), as written to run.json.
nlohmann::json sceneToJson(const Scene& scene);

// The JSON Schema of scene files (committed as scenes/schema.json).
nlohmann::json sceneSchema();

}  // namespace kurage::pipeline
