// A scene: everything a run needs, loaded strictly from a JSON file. Each component is a typed
// parameter struct (sim/, render/ or below); pipeline/scene_params.h is the single registry of
// their JSON keys, units, defaults and valid ranges, from which the loader, run.json and
// scenes/schema.json are all derived.
#pragma once

#include "pipeline/param_visitor.h"
#include "render/surfacing.h"
#include "render/tracer.h"
#include "sim/params.h"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>
#include <vector>

namespace kurage::pipeline {

struct OutputParams {
  float duration = 4.0f;  // s of simulated time
  float fps = 24.0f;      // frames per second; frame f is at time f / fps, f = 0 .. frameCount()-1

  int frameCount() const;
  double frameTime(int frame) const { return frame / double(fps); }
};

struct SurfaceParams {
  render::MetaballParams fluid;
};

struct MaterialParams {
  Eigen::Vector3f albedo{0.25f, 0.45f, 0.85f};
};

struct RenderParams {
  render::RenderSettings settings;  // resolution, samples, sky and ambient (flat in the JSON)
  render::Camera camera;
  render::DirectionalLight light;
  render::Ground ground;
  MaterialParams fluidMaterial;
};

struct Scene {
  std::string name = "scene";
  std::string description;
  sim::SimParams sim;
  OutputParams output;
  SurfaceParams surface;
  RenderParams render;
};

// Loads and validates a scene. Throws SceneError (file + JSON path) on any problem: unreadable
// file, JSON syntax, unknown keys, wrong types, missing required values, out-of-range values,
// and inconsistencies between components (a fluid block outside the container, ...).
Scene loadScene(const std::filesystem::path& file);

// Same, from an already parsed document; `file` is only used in messages.
Scene parseScene(const nlohmann::json& document, const std::string& file);

// The parameters in effect (after defaults), as written to run.json.
nlohmann::json sceneToJson(const Scene& scene);

// The JSON Schema of scene files (committed as scenes/schema.json).
nlohmann::json sceneSchema();

}  // namespace kurage::pipeline
