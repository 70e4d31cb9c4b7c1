#include "pipeline/scene.h"

#include "pipeline/io/files.h"
#include "pipeline/io/json_file.h"
#include "pipeline/scene_params.h"
#include "render/surfacing.h"
#include "sim/bodies.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <unistd.h>
#include <unordered_set>
#include <vector>

namespace kurage::pipeline {

int OutputParams::frameCount() const { return static_cast<int>(std::floor(double(duration) * fps + 1e-6)) + 1; }

void applyQuality(Scene& scene, Quality quality) {
  if (quality == Quality::Final) return;
  const PreviewQuality& q = scene.previewQuality;
  render::RenderSettings& r = scene.render.settings;
  r.width = q.width > 0 ? q.width : std::max(1, r.width / 2);
  r.height = q.height > 0 ? q.height : std::max(1, r.height / 2);
  r.samplesPerPixel = q.samples > 0 ? q.samples : std::max(1, r.samplesPerPixel / 4);
  r.maxDepth = q.maxDepth > 0 ? q.maxDepth : std::min(r.maxDepth, 6);
  scene.surface.fluid.voxelSize *= q.voxelScale;
  scene.surface.bodies.voxelSize *= q.voxelScale;
  if (q.fps > 0.0f) scene.output.fps = q.fps;
}

namespace {

std::string vec(const Eigen::Vector3f& v) {
  std::ostringstream s;
  s << "[" << v.x() << ", " << v.y() << ", " << v.z() << "]";
  return s.str();
}

std::string formatCount(double v) {
  std::ostringstream s;
  s.precision(3);
  s << v;
  return s.str();
}

// The output file names are made from `name`: it must be a plain file name.
void checkName(const std::string& name, const std::string& file) {
  std::string why;
  if (name.empty()) why = "must not be empty";
  else if (name.find('\0') != std::string::npos) why = "must not contain a NUL character";
  else if (name.find('/') != std::string::npos || name.find('\\') != std::string::npos)
    why = "must be a plain file name, without / or \\";
  else if (name == "." || name == "..") why = "must be a plain file name, not . or ..";
  else if (name.size() > 200) why = "must be at most 200 bytes long";
  else
    for (const char c : name)
      if (static_cast<unsigned char>(c) < 0x20) why = "must not contain control characters";
  if (!why.empty()) throw SceneError(file, "name", why + ", got " + jsonExcerpt(name));
}

}  // namespace

void checkSceneLimits(const Scene& scene, const std::string& file, const LoadOptions& options) {
  const SceneEstimate e = estimateScene(scene);
  const std::string hint = "; --force runs it anyway";
  if (e.frames > kMaxFramesHard)
    throw SceneError(file, "output.duration", "gives " + formatCount(e.frames) + " frames at output.fps, above the limit of " +
                                                 formatCount(kMaxFramesHard));
  if (e.gridCells > kMaxGridCells)
    throw SceneError(file, "container", "needs a neighbour grid of " + formatCount(e.gridCells) +
                                            " cells (container size / support radius), above the limit of " +
                                            formatCount(kMaxGridCells) + "; a smaller container or larger spacing fits");
  if (options.force) return;
  if (e.frames > kMaxFrames)
    throw SceneError(file, "output.duration", "gives " + formatCount(e.frames) + " frames, above the limit of " +
                                                 formatCount(kMaxFrames) + hint);
  if (e.springs > kMaxSprings)
    throw SceneError(file, "bodies[" + std::to_string(e.mostSpringsBody) + "].spacing",
                     "the bodies would have about " + formatCount(e.springs) + " springs (" +
                         formatCount(e.bodyParticles) + " particles, each joined to those within its connection "
                         "radius), above the limit of " + formatCount(kMaxSprings) +
                         "; a larger spacing or a smaller connection_radius fits" + hint);
  if (e.particles > kMaxParticles)
    throw SceneError(file, "fluid_blocks", "hold about " + formatCount(e.particles) + " particles, above the limit of " +
                                               formatCount(kMaxParticles) + hint);
  if (e.steps > kMaxSteps) {
    const bool fixed = scene.sim.timeStep.mode == sim::TimeStepMode::Fixed;
    throw SceneError(file, fixed ? "time_step.fixed_step" : "time_step.max_step",
                     "gives at least " + formatCount(e.steps) + " time steps over output.duration, above the limit of " +
                         formatCount(kMaxSteps) + hint);
  }
  const double physical = double(::sysconf(_SC_PHYS_PAGES)) * double(::sysconf(_SC_PAGE_SIZE));
  const std::string machine = ", more than this machine's " + formatCount(physical / 1e9) + " GB" + hint;
  if (physical > 0 && e.memoryBytes > physical)
    throw SceneError(file, "fluid.spacing", "the simulation needs about " + formatCount(e.memoryBytes / 1e9) + " GB (" +
                                                formatCount(e.particles) + " particles, " + formatCount(e.gridCells) +
                                                " grid cells)" + machine);
  if (physical > 0 && e.surfaceBytes > physical) {
    const bool bodies = scene.surface.bodies.voxelSize < scene.surface.fluid.voxelSize && e.bodyParticles > 0;
    throw SceneError(file, bodies ? "surface.bodies.voxel_size" : "surface.fluid.voxel_size",
                     "surfacing a frame needs up to " + formatCount(e.surfaceBytes / 1e9) + " GB (" +
                         formatCount(e.surfaceLeaves) + " leaves of 8^3 voxels)" + machine);
  }
  if (physical > 0 && e.renderBytes > physical)
    throw SceneError(file, "render.width", "rendering a frame needs up to " + formatCount(e.renderBytes / 1e9) +
                                               " GB (" + std::to_string(scene.render.settings.width) + " x " +
                                               std::to_string(scene.render.settings.height) +
                                               " pixels, the surfaces' meshes)" + machine);
}

namespace {

// Checks that need more than one field: they name the JSON path of the offending value.
void validate(const Scene& scene, const std::string& file) {
  auto fail = [&file](const std::string& path, const std::string& message) { throw SceneError(file, path, message); };
  checkName(scene.name, file);
  const sim::SimParams& sim = scene.sim;
  const sim::ContainerParams& box = sim.container;
  const float h = sim.fluid.supportRadiusMetres();
  for (int a = 0; a < 3; ++a)
    if (!(box.max[a] > box.min[a]))
      fail("container.max", "must exceed container.min on every axis, got min " + vec(box.min) + ", max " + vec(box.max));
  if (box.wallDensity == sim::WallDensity::BoundaryParticles && (box.max - box.min).minCoeff() < h) {
    std::ostringstream s;
    s << "boundary particles need a container at least one support radius h = " << h
      << " m across on every axis (the samples behind opposite walls would overlap every particle's support "
         "and count twice), got a size of "
      << vec(box.max - box.min);
    fail("container.wall_density", s.str());
  }
  if (const std::optional<sim::ParamProblem> problem = sim::pressureSolverProblem(sim.fluid))
    fail(problem->key, problem->message);
  if (sim.fluid.packing == sim::StartPacking::Relaxed) {
    sim::FluidParams resolved = sim.fluid;
    resolved.kernel = sim::resolvedKernel(resolved, box.wallDensity);
    if (sim::densityKernelOf(resolved) != sim::DensityKernel::CubicSpline)
      fail("fluid.packing", "'relaxed' needs the cubic-spline density kernel (fluid.kernel \"cubic_spline\"): the "
                            "paper's poly6 sum has no relaxed packing to start on");
  }
  if ((box.max - box.min).minCoeff() < h) {
    std::ostringstream s;
    s << "the container is smaller than the support radius h = " << h << " m on some axis (size "
      << vec(box.max - box.min) << ")";
    fail("container", s.str());
  }
  const float tolerance = 1e-4f * sim.fluid.spacing;
  for (size_t i = 0; i < sim.fluidBlocks.size(); ++i) {
    const sim::FluidBlock& b = sim.fluidBlocks[i];
    const std::string path = "fluid_blocks[" + std::to_string(i) + "]";
    for (int a = 0; a < 3; ++a)
      if (!(b.max[a] > b.min[a])) fail(path + ".max", "must exceed min on every axis, got min " + vec(b.min) + ", max " + vec(b.max));
    if ((b.min.array() < box.min.array() - tolerance).any() || (b.max.array() > box.max.array() + tolerance).any())
      fail(path, "lies outside the container " + vec(box.min) + " - " + vec(box.max));
    if (((b.max - b.min).array() < sim.fluid.spacing * (1.0f - 1e-4f)).any())
      fail(path, "is thinner than one particle spacing on some axis, so it holds no particle");
    for (size_t k = 0; k < i; ++k) {
      const sim::FluidBlock& o = sim.fluidBlocks[k];
      const bool overlap = ((b.min.array() < o.max.array() - tolerance) && (o.min.array() < b.max.array() - tolerance)).all();
      if (overlap) fail(path, "overlaps fluid_blocks[" + std::to_string(k) + "]");
    }
  }
  for (size_t i = 0; i < sim.emitters.size(); ++i) {
    const sim::EmitterParams& e = sim.emitters[i];
    const std::string path = "emitters[" + std::to_string(i) + "]";
    if (e.direction.norm() <= 0.0f) fail(path + ".direction", "must not be zero");
    if (!(e.end > e.start)) fail(path + ".end", "must be after start");
    if (e.radius < 0.5f * sim.fluid.spacing)
      fail(path + ".radius", "must be at least half the fluid spacing, or the nozzle emits nothing");
    if ((e.position.array() - e.radius < box.min.array()).any() || (e.position.array() + e.radius > box.max.array()).any())
      fail(path, "the nozzle at " + vec(e.position) + " with radius " + std::to_string(e.radius) +
                     " m lies (partly) outside the container");
  }
  for (size_t i = 0; i < sim.sinks.size(); ++i) {
    const sim::SinkParams& k = sim.sinks[i];
    for (int a = 0; a < 3; ++a)
      if (!(k.max[a] > k.min[a]))
        fail("sinks[" + std::to_string(i) + "].max", "must exceed min on every axis, got min " + vec(k.min) + ", max " + vec(k.max));
  }
  for (size_t i = 0; i < sim.bodies.size(); ++i) {
    const sim::BodyParams& b = sim.bodies[i];
    const std::string path = "bodies[" + std::to_string(i) + "]";
    if (b.shape == sim::BodyShape::Box || b.shape == sim::BodyShape::Membrane)
      for (int a = 0; a < (b.shape == sim::BodyShape::Box ? 3 : 2); ++a)
        if (!(b.max[a] > b.min[a])) fail(path + ".max", "must exceed min on every axis, got min " + vec(b.min) + ", max " + vec(b.max));
    if (b.shape == sim::BodyShape::Shell && b.axis.norm() <= 0.0f) fail(path + ".axis", "must not be zero");
    if (b.shape == sim::BodyShape::Chain && (b.end - b.start).norm() <= 0.0f) fail(path + ".end", "must differ from start");
    if (b.shape != sim::BodyShape::Chain && !b.attachTo.empty()) fail(path + ".attach_to", "only a chain can be attached");
    if (b.coupling == sim::BodyCoupling::Boundary)
      if (const std::string why = sim::boundaryCouplingProblem(sim.fluid); !why.empty()) fail(path + ".coupling", why);
    // The points that span the body, checked against the container before anything is built (a
    // chain starting 100 km away kept the loader busy for minutes: found by the scene fuzzer).
    const auto inside = [&box](const Eigen::Vector3f& q) {
      return (q.array() >= box.min.array()).all() && (q.array() <= box.max.array()).all();
    };
    const auto outside = [&](const char* key, const Eigen::Vector3f& q) {
      if (!inside(q)) fail(path + "." + key, vec(q) + " lies outside the container");
    };
    if (b.shape == sim::BodyShape::Box || b.shape == sim::BodyShape::Membrane) {
      outside("min", b.min);
      outside("max", b.max);
    }
    if (b.shape == sim::BodyShape::Chain) {
      outside("start", b.start);
      outside("end", b.end);
    }
    for (size_t k = 0; k < b.pins.size(); ++k)
      if (b.pins[k].kind == sim::SelectionKind::Region && ((b.pins[k].max - b.pins[k].min).array() < 0.0f).any())
        fail(path + ".pins[" + std::to_string(k) + "].max", "must not be below min on any axis");
    for (size_t m = 0; m < b.muscles.size(); ++m) {
      const std::string mp = path + ".muscles[" + std::to_string(m) + "]";
      const sim::ForceCurve& c = b.muscles[m].force;
      if (c.type == sim::CurveType::Keys && c.keys.empty()) fail(mp + ".force.keys", "a 'keys' curve needs at least one key");
      for (size_t k = 1; k < c.keys.size(); ++k)
        if (!(c.keys[k].time > c.keys[k - 1].time))
          fail(mp + ".force.keys[" + std::to_string(k) + "].time", "must be later than the key before");
      if (c.type == sim::CurveType::Pulse && !(c.end > c.start)) fail(mp + ".force.end", "must be after start");
      for (size_t o = 0; o < m; ++o)
        if (b.muscles[o].name == b.muscles[m].name) fail(mp + ".name", "\"" + b.muscles[m].name + "\" is used twice in this body");
    }
  }
  const sim::TimeStepParams& ts = sim.timeStep;
  if (ts.minStep > ts.maxStep) fail("time_step.min_step", "must not exceed time_step.max_step");
  const render::Camera& cam = scene.render.camera;
  if ((cam.position - cam.lookAt).norm() <= 0.0f) fail("render.camera.look_at", "must differ from the camera position");
  if (cam.up.cross(cam.lookAt - cam.position).norm() <= 1e-6f * cam.up.norm() * (cam.lookAt - cam.position).norm())
    fail("render.camera.up", "must not be parallel to the viewing direction");
  if (scene.render.sun.direction.norm() <= 0.0f) fail("render.light.direction", "must not be zero");
  const RenderParams& render = scene.render;
  if (render.bitDepth != 8 && render.bitDepth != 16) fail("render.bit_depth", "must be 8 or 16");
  if (!render.outputs.png && !render.outputs.exr)
    fail("render.outputs", "writes no frame: set png or exr (or both) to true");
  if (render.settings.denoise.enabled && render.settings.integrator == render::IntegratorType::Whitted)
    fail("render.denoise.enabled", "the whitted integrator makes no noise and gathers no albedo and normal buffers "
                                   "for the denoiser; use the path integrator");
  const render::AdaptiveSettings& adaptive = render.settings.adaptive;
  if (adaptive.maxSamples < adaptive.minSamples)
    fail("render.adaptive.max_samples", "must be at least min_samples (" + std::to_string(adaptive.minSamples) +
                                            "), got " + std::to_string(adaptive.maxSamples));
  for (size_t i = 1; i < render.cameraKeys.size(); ++i)
    if (!(render.cameraKeys[i].time > render.cameraKeys[i - 1].time))
      fail("render.camera_keys[" + std::to_string(i) + "].time", "must be later than the key before");
  for (size_t i = 0; i < render.cameraKeys.size(); ++i)
    if ((render.cameraKeys[i].lookAt - render.cameraKeys[i].position).cross(cam.up).norm() <= 0.0f)
      fail("render.camera_keys[" + std::to_string(i) + "].look_at", "must differ from position and not lie along camera.up");
  for (size_t i = 0; i < render.areaLights.size(); ++i)
    if (render.areaLights[i].edgeU.cross(render.areaLights[i].edgeV).norm() <= 0.0f)
      fail("render.area_lights[" + std::to_string(i) + "].edge_v", "must not be parallel to edge_u (zero area)");
  if (render.environment.type == render::EnvironmentType::Image && render.environment.image.empty())
    fail("render.environment.image", "is required when the type is \"image\"");
  if (render.clip.enabled && render.clip.normal.norm() <= 0.0f) fail("render.clip.normal", "must not be zero");
  if (scene.render.ground.normal.norm() <= 0.0f) fail("render.ground.normal", "must not be zero");
  const render::MetaballParams& blob = scene.surface.fluid;
  if (blob.threshold >= blob.strength)
    fail("surface.fluid.threshold", "must be below the blob strength, or a single particle has no surface");
  if (blob.voxelSize >= blob.radius) fail("surface.fluid.voxel_size", "must be smaller than surface.fluid.radius");
  const render::AirborneParams& air = scene.surface.airborne;
  if (air.enabled && air.radius > blob.radius) fail("surface.airborne.radius", "must not exceed surface.fluid.radius");
  if (!(air.speedFull > air.speedMin)) fail("surface.airborne.speed_full", "must exceed speed_min");
  if (!(air.fillMin > air.fillFull)) fail("surface.airborne.fill_min", "must exceed fill_full");
}

// The 8^3-voxel leaves a metaball field can touch (SceneEstimate::surfaceLeaves): `particles`
// blobs of radius R and `stretched` ones of up to kMaxRadiusScale R (render::stretchRadiusScales).
double metaballLeaves(const render::MetaballParams& m, const sim::ContainerParams& box, double particles,
                      double stretched = 0.0) {
  const double leaf = 8.0 * double(m.voxelSize);
  const auto perBlob = [&](double reach) {
    const double along = std::ceil((reach / double(m.voxelSize) + 1.0) / 8.0) + 1.0;
    return along * along * along;
  };
  const double reach = 2.0 * double(m.radius), stretchedReach = reach * double(render::kMaxRadiusScale);
  const double widest = stretched > 0.0 ? stretchedReach : reach;
  double overContainer = 1.0;
  for (int a = 0; a < 3; ++a) overContainer *= std::floor((double(box.max[a]) - box.min[a] + widest) / leaf) + 2.0;
  return std::min(overContainer, particles * perBlob(reach) + stretched * perBlob(stretchedReach));
}

}  // namespace

SceneEstimate estimateScene(const Scene& scene) {
  SceneEstimate e;
  const sim::SimParams& sim = scene.sim;
  const double spacing = sim.fluid.spacing;
  for (const sim::FluidBlock& b : sim.fluidBlocks) {
    double n = 1.0;
    for (int a = 0; a < 3; ++a) n *= std::floor((double(b.max[a]) - b.min[a]) / spacing + 1e-4);
    e.particles += std::max(0.0, n);
  }
  const double h = sim.fluid.supportRadiusMetres();
  e.gridCells = 1.0;
  for (int a = 0; a < 3; ++a)
    e.gridCells *= std::max(1.0, std::ceil((double(sim.container.max[a]) - sim.container.min[a]) / h));
  e.frames = std::floor(double(scene.output.duration) * scene.output.fps + 1e-6) + 1.0;
  double mostSprings = -1.0;
  double stretchable = 0.0;  // particles of bodies with telescopic density, whose blobs grow when stretched
  for (size_t b = 0; b < sim.bodies.size(); ++b) {
    const sim::BodyParams& body = sim.bodies[b];
    const double s = body.spacingMetres(sim.fluid.spacing);
    const auto along = [s](double length) { return std::floor(std::max(length, 0.0) / s + 1e-4) + 1.0; };
    double n = 0.0;
    switch (body.shape) {
      case sim::BodyShape::Box:
        n = along(body.max.x() - body.min.x()) * along(body.max.y() - body.min.y()) * along(body.max.z() - body.min.z());
        break;
      case sim::BodyShape::Membrane:
        n = along(body.max.x() - body.min.x()) * along(body.max.y() - body.min.y()) * std::max(body.layers, 1);
        break;
      case sim::BodyShape::Shell: {
        const double outer = double(body.innerRadius) + body.layers * s + s;
        const double cap = 2.0 * M_PI * outer * outer * (1.0 - std::cos(double(body.openingAngle) * M_PI / 180.0));
        n = std::max(body.layers, 1) * (cap / (s * s) * 1.25 + 1.0);
        break;
      }
      case sim::BodyShape::Chain: n = along((body.end - body.start).norm()); break;
    }
    const double reach = double(body.connectionRadius) * sim.fluid.spacing / s;  // h_spr in body spacings
    const double springs = n * std::min(n, 4.0 / 3.0 * M_PI * reach * reach * reach) / 2.0;
    e.bodyParticles += n;
    if (body.telescopicDensity) stretchable += n;
    e.springs += springs;
    if (springs > mostSprings) {
      mostSprings = springs;
      e.mostSpringsBody = b;
    }
  }
  e.memoryBytes = (e.particles + e.bodyParticles) * kBytesPerParticle + e.gridCells * 12.0 + e.springs * 32.0;
  e.steps = estimateSteps(scene, scene.output.duration);
  const double fluidParticles = sim.emitters.empty() ? e.particles : HUGE_VAL;
  e.surfaceLeaves = metaballLeaves(scene.surface.fluid, sim.container, fluidParticles);
  if (e.bodyParticles > 0)
    e.surfaceLeaves += metaballLeaves(scene.surface.bodies, sim.container, e.bodyParticles - stretchable, stretchable);
  e.surfaceBytes = e.surfaceLeaves * kBytesPerSurfaceLeaf;
  e.renderBytes = double(scene.render.settings.width) * scene.render.settings.height * kBytesPerPixel + e.surfaceBytes;
  return e;
}

double estimateSteps(const Scene& scene, double seconds) {
  const sim::TimeStepParams& ts = scene.sim.timeStep;
  return std::ceil(seconds / double(ts.mode == sim::TimeStepMode::Fixed ? ts.fixedStep : ts.maxStep));
}

Scene parseScene(const nlohmann::json& document, const std::string& file, const LoadOptions& options) {
  if (!document.is_object()) throw SceneError(file, "", "a scene must be a JSON object");
  Scene scene;
  JsonReader reader(document, file, "");
  describe(reader, scene);
  reader.finish();
  validate(scene, file);
  checkSceneLimits(scene, file, options);
  // Building the bodies to check them costs time and memory: only once the limits hold.
  if (!scene.sim.bodies.empty()) {
    const std::vector<sim::BodyProblem> problems = sim::checkBodies(scene.sim);
    if (!problems.empty()) {
      const sim::BodyProblem& p = problems.front();
      throw SceneError(file, "bodies[" + std::to_string(p.body) + "]" + (p.field.empty() ? "" : "." + p.field), p.message);
    }
  }
  return scene;
}

// Parses JSON text, refusing duplicate keys (nlohmann keeps the last silently) and nesting deeper
// than kMaxJsonDepth (checked on the text first, so the parser never builds a deep value). A
// level keeps only its own name and its keys; the JSON path of a duplicate is joined only when
// one is found, so memory stays linear in the text.
nlohmann::json parseStrictJson(const std::string& s, const std::string& file) {
  if (const size_t at = jsonDepthBeyond(s); at != std::string::npos)
    throw SceneError(file, "", "nested deeper than " + std::to_string(kMaxJsonDepth) + " levels at " +
                                   lineAndColumn(s, at));
  struct Level {
    std::string name;  // the key this level is the value of, or "[]" for an array's item
    std::unordered_set<std::string> keys;
  };
  std::vector<Level> levels;
  std::string lastKey;
  const auto pathTo = [&](const std::string& key) {
    std::string path;
    for (size_t i = 1; i < levels.size(); ++i)
      path += levels[i].name == "[]" || path.empty() ? levels[i].name : "." + levels[i].name;
    return key.empty() ? path : path.empty() ? key : path + "." + key;
  };
  const nlohmann::json::parser_callback_t callback = [&](int, nlohmann::json::parse_event_t event,
                                                          nlohmann::json& parsed) {
    using E = nlohmann::json::parse_event_t;
    if (event == E::object_start || event == E::array_start) {
      levels.push_back({lastKey.empty() ? "[]" : lastKey, {}});
      lastKey.clear();
    } else if (event == E::object_end || event == E::array_end) {
      if (!levels.empty()) levels.pop_back();
      lastKey.clear();
    } else if (event == E::key) {
      lastKey = parsed.get<std::string>();
      if (!levels.back().keys.insert(lastKey).second)
        throw SceneError(file, pathTo(lastKey),
                         "duplicate key " + jsonExcerpt(lastKey) + " (JSON keeps only one of them)");
    } else if (event == E::value) {
      lastKey.clear();
    }
    return true;
  };
  try {
    return nlohmann::json::parse(s, callback);
  } catch (const nlohmann::json::parse_error& e) {
    throw SceneError(file, "", "invalid JSON at " + lineAndColumn(s, e.byte > 0 ? e.byte - 1 : 0) + ": " + e.what());
  } catch (const nlohmann::json::exception& e) {  // e.g. a number beyond a double (1e400)
    throw SceneError(file, "", std::string("invalid JSON: ") + e.what());
  }
}

Scene loadScene(const std::filesystem::path& file, const LoadOptions& options) {
  std::string text;
  try {
    text = readFile(file, kMaxJsonBytes);
  } catch (const IoError& e) {
    throw SceneError(file.string(), "", std::string("cannot read the scene file: ") + e.what());
  }
  return parseScene(parseStrictJson(text, file.string()), file.string(), options);
}

nlohmann::json sceneToJson(const Scene& scene) {
  Scene copy = scene;
  nlohmann::json out;
  JsonWriter writer(out);
  describe(writer, copy);
  return out;
}

nlohmann::json sceneSchema() {
  Scene defaults;
  nlohmann::json schema;
  SchemaWriter writer(schema);
  describe(writer, defaults);
  nlohmann::json document = {
      {"$schema", "https://json-schema.org/draft/2020-12/schema"},
      {"title", "kurage scene"},
      {"description", "A kurage scene: fluid, container, output, surfacing and rendering parameters. "
                      "Generated by `kurage schema`; do not edit by hand."}};
  document.update(schema);
  return document;
}

}  // namespace kurage::pipeline
