// Scene loading (pipeline/scene.h): strict validation with file + JSON path, the schema kept in
// step with the parameter structs, and the CLI refusing bad scenes before writing anything.
#include "pipeline/io/files.h"
#include "pipeline/scene.h"
#include "render/surfacing.h"
#include "test_util.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <fstream>
#include <functional>

using namespace kurage;
using namespace kurage::pipeline;
using nlohmann::json;

namespace {

json baseScene() {
  return json::parse(readText(test::sourceDir() / "tests/scenes/tiny_dam_break.json"));
}

// Appends a valid 2 m box body clear of the fluid block and returns it.
json& addBox(json& s) {
  s["bodies"].push_back({{"name", "box"}, {"shape", "box"}, {"min", {8, 1, 1}}, {"max", {10, 3, 3}}});
  return s["bodies"].back();
}

struct BadScene {
  const char* name;
  std::function<void(json&)> mutate;  // applied to the valid base scene
  const char* path;                   // the JSON path the message must name
  const char* message;                // a fragment the message must contain
};

std::ostream& operator<<(std::ostream& os, const BadScene& s) { return os << s.name; }

const BadScene kBadScenes[] = {
    {"UnknownSolver", [](json& s) { s["fluid"]["solver"] = "pcisph"; }, "fluid.solver",
     "must be one of \"wcsph\", \"dfsph\""},
    {"ZeroDensityTolerance", [](json& s) {
       s["fluid"]["solver"] = "dfsph";
       s["fluid"]["max_density_error"] = 0;
     }, "fluid.max_density_error", "must be > 0, got 0"},
    {"NegativeDivergenceTolerance", [](json& s) {
       s["fluid"]["solver"] = "dfsph";
       s["fluid"]["max_divergence_error"] = -1;
     }, "fluid.max_divergence_error", "must be > 0, got -1"},
    {"ZeroIterationCap", [](json& s) {
       s["fluid"]["solver"] = "dfsph";
       s["fluid"]["max_iterations"] = 0;
     }, "fluid.max_iterations", "must be >= 1, got 0"},
    {"UnknownDivergenceSolve", [](json& s) {
       s["fluid"]["solver"] = "dfsph";
       s["fluid"]["divergence_solve"] = "gmres";
     }, "fluid.divergence_solve", "must be one of \"jacobi\", \"cg\", got \"gmres\""},
    // A solver's keys are read only under that solver: elsewhere they would be ignored.
    {"DfsphKeyUnderWcsph", [](json& s) { s["fluid"]["divergence_solve"] = "cg"; }, "fluid.divergence_solve",
     "unknown key"},
    {"DfsphWithThePapersKernels", [](json& s) {
       s["fluid"]["solver"] = "dfsph";
       s["fluid"]["kernel"] = "mueller2003";
     }, "fluid.kernel", "dfsph's solves use the cubic spline"},
    {"GradientCorrectionOfThePapersForce", [](json& s) { s["fluid"]["gradient_correction"] = true; },
     "fluid.gradient_correction", "the paper's force \"mueller2003\" has no corrected form"},
    {"BoundaryCouplingUnderWcsph", [](json& s) { addBox(s)["coupling"] = "boundary"; }, "bodies[0].coupling",
     "\"boundary\" needs a solver that couples bodies as the fluid's boundary (fluid.solver \"dfsph\"), got \"wcsph\""},
    {"BoundaryCouplingWithTheMassSum", [](json& s) {
       s["fluid"]["solver"] = "dfsph";
       s["fluid"]["density_sum"] = "mass";
       addBox(s)["coupling"] = "boundary";
     }, "bodies[0].coupling", "needs fluid.density_sum \"volume\""},
    {"BoundaryCouplingWithConjugateGradients", [](json& s) {
       s["fluid"]["solver"] = "dfsph";
       s["fluid"]["density_sum"] = "volume";
       s["fluid"]["divergence_solve"] = "cg";
       addBox(s)["coupling"] = "boundary";
     }, "bodies[0].coupling", "needs fluid.divergence_solve \"jacobi\""},
    {"BoundaryCouplingUnderIisph", [](json& s) {
       s["fluid"]["solver"] = "iisph";
       addBox(s)["coupling"] = "boundary";
     }, "bodies[0].coupling", "(fluid.solver \"dfsph\"), got \"iisph\""},
    {"IisphWithTheGradientCorrection", [](json& s) {
       s["fluid"]["solver"] = "iisph";
       s["fluid"]["gradient_correction"] = true;
     }, "fluid.gradient_correction", "iisph has no corrected kernel gradient"},
    {"IisphRelaxationAboveOne", [](json& s) {
       s["fluid"]["solver"] = "iisph";
       s["fluid"]["relaxation"] = 1.5;
     }, "fluid.relaxation", "must be <= 1, got 1.5"},
    {"UnknownCoupling", [](json& s) { addBox(s)["coupling"] = "glued"; }, "bodies[0].coupling",
     "must be one of \"solved\", \"boundary\", got \"glued\""},
    {"RelaxedPackingWithThePapersKernels", [](json& s) { s["fluid"]["packing"] = "relaxed"; }, "fluid.packing",
     "'relaxed' needs the cubic-spline density kernel"},
    {"UnknownPacking", [](json& s) { s["fluid"]["packing"] = "hexagonal"; }, "fluid.packing",
     "must be one of \"lattice\", \"relaxed\", got \"hexagonal\""},
    {"UnknownKernel", [](json& s) { s["fluid"]["kernel"] = "wendland"; }, "fluid.kernel",
     "must be one of \"auto\", \"mueller2003\", \"cubic_spline\", got \"wendland\""},
    {"BoundaryParticlesThinContainer", [](json& s) {
       s["container"]["wall_density"] = "boundary_particles";
       s["container"]["max"] = {16, 1.2, 10};
       s["fluid_blocks"][0]["max"] = {4, 1.2, 4};
     }, "container.wall_density", "boundary particles need a container at least one support radius"},
    {"UnknownTopLevelKey", [](json& s) { s["fluids"] = json::object(); }, "fluids", "unknown key"},
    {"MisspelledNestedKey", [](json& s) { s["fluid"]["spaceing"] = 1.0; }, "fluid.spaceing",
     "unknown key (did you mean \"spacing\"?)"},
    {"WrongType", [](json& s) { s["fluid"]["spacing"] = "1.0"; }, "fluid.spacing", "must be a number, got \"1.0\""},
    {"NegativeSpacing", [](json& s) { s["fluid"]["spacing"] = -3; }, "fluid.spacing", "must be > 0, got -3"},
    {"ZeroSupportRadius", [](json& s) { s["fluid"]["support_radius"] = 0; }, "fluid.support_radius",
     "must be >= 1, got 0"},
    {"MissingContainer", [](json& s) { s.erase("container"); }, "container", "is required but missing"},
    {"MissingContainerMin", [](json& s) { s["container"].erase("min"); }, "container.min", "is required but missing"},
    {"BadEnum", [](json& s) { s["container"]["walls"] = "sticky"; }, "container.walls",
     "must be one of \"no_slip\", \"free_slip\", got \"sticky\""},
    {"VectorTooShort", [](json& s) { s["gravity"] = {0, -6}; }, "gravity", "must be an array of 3 numbers"},
    {"UnknownIntegrator", [](json& s) { s["render"]["integrator"] = "bidirectional"; }, "render.integrator",
     "must be one of \"path\", \"whitted\", got \"bidirectional\""},
    {"AdaptiveErrorNotPositive", [](json& s) { s["render"]["adaptive"]["relative_error"] = 0; },
     "render.adaptive.relative_error", "must be > 0, got 0"},
    {"AdaptiveMaxBelowMin", [](json& s) {
       s["render"]["adaptive"] = json::parse(R"({"enabled": true, "min_samples": 16, "max_samples": 8})");
     }, "render.adaptive.max_samples", "must be at least min_samples (16), got 8"},
    {"DenoiserWithoutItsBuffers", [](json& s) {
       s["render"]["integrator"] = "whitted";
       s["render"]["denoise"]["enabled"] = true;
     }, "render.denoise.enabled", "gathers no albedo and normal buffers"},
    {"NoFrameOutput", [](json& s) { s["render"]["outputs"] = json::parse(R"({"png": false, "exr": false})"); },
     "render.outputs", "writes no frame"},
    {"WhittedNoSkyDirections", [](json& s) { s["render"]["whitted"]["sky_directions"] = 0; },
     "render.whitted.sky_directions", "must be >= 1, got 0"},
    {"VectorElementType", [](json& s) { s["fluid_blocks"][0]["min"][1] = true; }, "fluid_blocks[0].min[1]",
     "must be a number, got true"},
    {"NonIntegerWidth", [](json& s) { s["render"]["width"] = 64.5; }, "render.width", "must be an integer"},
    {"BlockOutsideContainer", [](json& s) { s["fluid_blocks"][0]["max"] = {5, 5, 30}; }, "fluid_blocks[0]",
     "lies outside the container"},
    {"OverlappingBlocks", [](json& s) { s["fluid_blocks"].push_back({{"min", {2, 0, 0}}, {"max", {6, 5, 4}}}); },
     "fluid_blocks[1]", "overlaps fluid_blocks[0]"},
    {"InvertedContainer", [](json& s) { s["container"]["max"] = {16, -5, 10}; }, "container.max",
     "must exceed container.min"},
    {"ContainerSmallerThanSupport", [](json& s) {
       s["container"]["max"] = {16, 1, 10};
       s["fluid_blocks"][0]["max"] = {5, 1, 8};
     }, "container", "smaller than the support radius"},
    {"CameraUpParallel", [](json& s) { s["render"]["camera"]["up"] = {0, 24.5, -10}; }, "render.camera.up",
     "parallel"},
    {"MissingDuration", [](json& s) { s["output"].erase("duration"); }, "output.duration", "is required but missing"},
    {"NotAnObject", [](json& s) { s["time_step"] = 0.01; }, "time_step", "must be an object"},
    {"ThresholdAboveStrength", [](json& s) { s["surface"]["fluid"]["threshold"] = 2.0; }, "surface.fluid.threshold",
     "must be below the blob strength"},
    {"BadSurfaceKernel", [](json& s) { s["surface"]["bodies"]["kernel"] = "ellipsoid"; }, "surface.bodies.kernel",
     "must be one of \"isotropic\", \"anisotropic\", got \"ellipsoid\""},
    {"AnisotropySmoothingAboveOne", [](json& s) { s["surface"]["fluid"]["anisotropy"]["smoothing"] = 1.5; },
     "surface.fluid.anisotropy.smoothing", "must be <= 1, got 1.5"},
    {"ClipNotABoolean", [](json& s) { s["surface"]["clip_to_container"] = 1; }, "surface.clip_to_container",
     "must be"},
    {"AirborneRadiusAboveR", [](json& s) { s["surface"]["airborne"] = {{"enabled", true}, {"radius", 50.0}}; },
     "surface.airborne.radius", "must not exceed surface.fluid.radius"},
    {"AirborneFillRampInverted", [](json& s) { s["surface"]["airborne"] = {{"fill_full", 0.5}, {"fill_min", 0.4}}; },
     "surface.airborne.fill_min", "must exceed fill_full"},
    {"FaucetsNotABoolean", [](json& s) { s["render"]["faucets"]["enabled"] = "yes"; }, "render.faucets.enabled",
     "must be"},
    // Bodies (one valid box body at [8, 1, 1] - [10, 3, 3] is added, then broken).
    {"BodyYieldsNoParticle", [](json& s) { addBox(s)["max"] = {8.2, 3, 3}; }, "bodies[0]", "yields no particle"},
    {"BodyConnectionRadiusJoinsNone", [](json& s) { addBox(s)["connection_radius"] = 0.3; },
     "bodies[0].connection_radius", "joins no spring"},
    {"BodyOutsideContainer", [](json& s) { addBox(s)["max"] = {10, 3, 12}; }, "bodies[0].max", "lies outside the container"},
    {"UnknownTelescopicMeasure", [](json& s) { addBox(s)["telescopic_measure"] = "volume"; },
     "bodies[0].telescopic_measure", "must be one of \"isotropic\", \"stretch_only\", got \"volume\""},
    {"BodiesOverlap", [](json& s) {
       addBox(s);
       json& b = addBox(s);
       b["name"] = "second";
       b["min"] = {9, 1, 1};
     }, "bodies[1]", "overlaps bodies[0]"},
    {"MuscleSelectsNoSpring", [](json& s) {
       addBox(s)["muscles"] = {{{"springs", {{"select", "region"}, {"min", {0, 0, 0}}, {"max", {1, 1, 1}}}},
                                {"force", {{"type", "pulse"}}}}};
     }, "bodies[0].muscles[0].springs", "selects no spring"},
    {"PinSelectsNothing", [](json& s) {
       addBox(s)["pins"] = {{{"select", "region"}, {"min", {0, 0, 0}}, {"max", {1, 1, 1}}}};
     }, "bodies[0].pins[0]", "selects no particle"},
    {"PartSelectsNothing", [](json& s) {
       addBox(s)["parts"] = {{{"particles", {{"select", "region"}, {"min", {0, 0, 0}}, {"max", {1, 1, 1}}}},
                              {"specific_gravity", 2.0}}};
     }, "bodies[0].parts[0].particles", "selects no particle"},
    {"PartWithoutSpecificGravity", [](json& s) {
       addBox(s)["parts"] = {{{"particles", {{"select", "all"}}}}};
     }, "bodies[0].parts[0].specific_gravity", "is required but missing"},
    {"ChainAttachedToMissingBody", [](json& s) {
       json& b = addBox(s);
       b["shape"] = "chain";
       b["start"] = {9, 1, 1};
       b["end"] = {9, 1, 3};
       b["attach_to"] = "bell";
     }, "bodies[0].attach_to", "no other body is named \"bell\""},
    {"BodyUnknownShape", [](json& s) { addBox(s)["shape"] = "sphere"; }, "bodies[0].shape", "must be one of"},
    {"MuscleKeysOutOfOrder", [](json& s) {
       addBox(s)["muscles"] = json::parse(R"([{"springs": {"select": "all"}, "force": {"type": "keys",
           "keys": [{"time": 2, "force": 1}, {"time": 1, "force": 0}]}}])");
     }, "bodies[0].muscles[0].force.keys[1].time", "must be later"},
};

class BadSceneTest : public ::testing::TestWithParam<BadScene> {};

}  // namespace

TEST_P(BadSceneTest, NamesFileAndJsonPath) {
  json scene = baseScene();
  GetParam().mutate(scene);
  try {
    parseScene(scene, "bad.json");
    FAIL() << "the scene was accepted";
  } catch (const SceneError& e) {
    EXPECT_EQ(e.file(), "bad.json");
    EXPECT_EQ(e.jsonPath(), GetParam().path) << e.what();
    EXPECT_NE(e.message().find(GetParam().message), std::string::npos) << e.what();
    EXPECT_EQ(std::string(e.what()), "bad.json: " + std::string(GetParam().path) + ": " + e.message());
  }
}

TEST_P(BadSceneTest, CliExitsNonZeroAndWritesNothing) {
  test::TempDir dir;
  json scene = baseScene();
  GetParam().mutate(scene);
  const auto file = dir.path() / "bad.json";
  writeTextAtomic(file, scene.dump(2));
  const auto out = dir.path() / "out";
  const int code = test::runKurage("run " + file.string() + " -o " + out.string(), dir.path() / "log.txt");
  EXPECT_EQ(code, 2);
  EXPECT_FALSE(std::filesystem::exists(out)) << "output folder created for a bad scene";
  const std::string log = readText(dir.path() / "log.txt");
  EXPECT_NE(log.find(file.string() + ": " + GetParam().path + ": "), std::string::npos) << log;
  EXPECT_EQ(test::runKurage("check " + file.string(), dir.path() / "log2.txt"), 2);
}

INSTANTIATE_TEST_SUITE_P(Scenes, BadSceneTest, ::testing::ValuesIn(kBadScenes),
                         [](const auto& info) { return std::string(info.param.name); });

TEST(SceneFile, InvalidJsonNamesFileAndLine) {
  test::TempDir dir;
  const auto file = dir.path() / "broken.json";
  writeTextAtomic(file, "{\n  \"name\": \"x\",\n  \"fluid\": { \"spacing\": 1.0, }\n}\n");
  try {
    loadScene(file);
    FAIL();
  } catch (const SceneError& e) {
    EXPECT_EQ(e.file(), file.string());
    EXPECT_NE(e.message().find("invalid JSON at line 3"), std::string::npos) << e.what();
  }
}

TEST(SceneFile, MissingFileIsAnError) {
  EXPECT_THROW(loadScene("/nonexistent/kurage/scene.json"), SceneError);
}

TEST(SceneFile, NanIsRefused) {
  // JSON has no NaN; a scene that spells one is refused as invalid JSON.
  test::TempDir dir;
  const auto file = dir.path() / "nan.json";
  std::string text = baseScene().dump(2);
  text.replace(text.find("\"spacing\": 1.0"), 14, "\"spacing\": NaN");
  writeTextAtomic(file, text);
  EXPECT_THROW(loadScene(file), SceneError);
}

TEST(SceneFile, DefaultsAreThePapersParameters) {
  json scene = baseScene();
  scene.erase("fluid");
  scene.erase("gravity");
  const Scene s = parseScene(scene, "x.json");
  EXPECT_FLOAT_EQ(s.sim.fluid.spacing, 1.0f);
  EXPECT_FLOAT_EQ(s.sim.fluid.supportRadius, 1.5f);
  EXPECT_FLOAT_EQ(s.sim.fluid.restDensity, 1000.0f);
  EXPECT_FLOAT_EQ(s.sim.fluid.pressureStiffness, 2.2f);
  EXPECT_FLOAT_EQ(s.sim.fluid.kinematicViscosity, 0.3f);
  EXPECT_FLOAT_EQ(s.sim.gravity.norm(), 6.0f);
}

TEST(SceneFile, EffectiveParametersRoundTrip) {
  const Scene s = loadScene(test::sourceDir() / "scenes/dam_break.json");
  const json effective = sceneToJson(s);
  const Scene again = parseScene(effective, "effective.json");
  EXPECT_EQ(sceneToJson(again), effective);
  EXPECT_EQ(effective["fluid"]["viscosity"], 0.3);  // written as the user wrote it, not 0.30000001
}

TEST(SceneFile, CommittedScenesAreValid) {
  for (const char* file : {"scenes/dam_break.json", "tests/scenes/tiny_dam_break.json"})
    EXPECT_NO_THROW(loadScene(test::sourceDir() / file)) << file;
}

TEST(Schema, CommittedSchemaMatchesTheParameterStructs) {
  const std::string committed = readText(test::sourceDir() / "scenes/schema.json");
  EXPECT_EQ(committed, sceneSchema().dump(2) + "\n")
      << "scenes/schema.json is stale: regenerate it with `build/kurage schema > scenes/schema.json`";
}

TEST(Schema, DescribesEveryKeyWithDefaultsAndRanges) {
  const json schema = sceneSchema();
  EXPECT_EQ(schema["additionalProperties"], false);
  const json& spacing = schema["properties"]["fluid"]["properties"]["spacing"];
  EXPECT_EQ(spacing["type"], "number");
  EXPECT_EQ(spacing["default"], 1.0);
  EXPECT_EQ(spacing["exclusiveMinimum"], 0.0);
  EXPECT_NE(spacing["description"].get<std::string>().find("[m]"), std::string::npos);
  EXPECT_EQ(schema["properties"]["container"]["properties"]["walls"]["enum"], json({"no_slip", "free_slip"}));
  EXPECT_NE(std::find(schema["required"].begin(), schema["required"].end(), "container"), schema["required"].end());
}

TEST(SceneFile, FixedStepAboveTheStabilityBoundWarnsOrFailsWithStrict) {
  test::TempDir dir;
  json scene = baseScene();
  scene["time_step"] = {{"mode", "fixed"}, {"fixed_step", 0.5}};
  scene["output"] = {{"duration", 0.5}, {"fps", 2}};
  const auto file = dir.path() / "big_step.json";
  writeTextAtomic(file, scene.dump(2));
  const auto out = dir.path() / "out";
  EXPECT_EQ(test::runKurage("sim " + file.string() + " -o " + out.string() + " --strict", dir.path() / "strict.txt"), 2);
  EXPECT_FALSE(std::filesystem::exists(out));
  const std::string strict = readText(dir.path() / "strict.txt");
  EXPECT_NE(strict.find("time_step.fixed_step: the fixed step"), std::string::npos) << strict;
  EXPECT_NE(strict.find("cfl stability bound"), std::string::npos) << strict;
  // Without --strict it is a warning naming the bound, and the run goes on (here it stops with a
  // clear error once the state becomes non-finite, or finishes: either way it says so).
  const int code = test::runKurage("sim " + file.string() + " -o " + out.string(), dir.path() / "warn.txt");
  const std::string warn = readText(dir.path() / "warn.txt");
  EXPECT_NE(warn.find("warning: " + file.string() + ": time_step.fixed_step"), std::string::npos) << warn;
  if (code != 0) {
    EXPECT_NE(warn.find("simulation stopped"), std::string::npos) << warn;
  }
}

// A telescopic body's stretched particles surface with blobs of up to kMaxRadiusScale R
// (render::stretchRadiusScales), so the surfacing memory bound counts them at that radius: as a
// conventional body's blobs of radius 2 R, more than at R (a large container, so that the bound
// is the blobs' and not the container's).
TEST(SceneEstimate, ATelescopicBodysBlobsAreBudgetedAtTheirLargestRadius) {
  json scene = baseScene();
  scene["container"]["max"] = {400, 400, 400};
  addBox(scene);
  const auto leaves = [&](bool telescopic, double radiusScale) {
    json s = scene;
    s["bodies"][0]["telescopic_density"] = telescopic;
    const Scene parsed = parseScene(s, "x.json");
    s["surface"]["bodies"]["radius"] = double(parsed.surface.bodies.radius) * radiusScale;
    json fluidOnly = s;
    fluidOnly.erase("bodies");
    return estimateScene(parseScene(s, "x.json")).surfaceLeaves -
           estimateScene(parseScene(fluidOnly, "x.json")).surfaceLeaves;
  };
  const double conventional = leaves(false, 1.0), telescopic = leaves(true, 1.0);
  EXPECT_GT(conventional, 0.0);
  EXPECT_GT(telescopic, 2.0 * conventional);  // equal at R
  EXPECT_EQ(telescopic, leaves(false, double(render::kMaxRadiusScale)));
}
