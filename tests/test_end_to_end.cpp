// End to end: a tiny dam break through every stage of the CLI, its last frame compared with a
// committed reference (tests/references/tiny_dam_break_0004.png).
//
// Tolerance: a pixel fails when a channel differs by more than 0.02 in sRGB-encoded value
// (5 of 255 levels; Blender's render tests use 0.016); the test passes when at most 2 % of the
// pixels fail (Blender: 1 %). The image is only 64x48, so one pixel is 0.03 %: 2 % allows about
// 60 pixels along the fluid's silhouette to move by a voxel between compilers/libraries.
// KURAGE_UPDATE_REFERENCES=1 rewrites the reference instead of comparing.
#include "pipeline/files.h"
#include "pipeline/particle_cache.h"
#include "render/image.h"
#include "test_util.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <iostream>

using namespace kurage;
namespace fs = std::filesystem;

namespace {

// Compares `actual` with the reference; on failure writes the new image and an amplified
// difference image beside the build and prints their paths.
void expectMatchesReference(const fs::path& actualPng, const std::string& name, const render::CompareOptions& options) {
  const fs::path reference = test::sourceDir() / "tests/references" / (name + ".png");
  const render::Image actual = render::readPng(actualPng);
  if (std::getenv("KURAGE_UPDATE_REFERENCES")) {
    fs::create_directories(reference.parent_path());
    fs::copy_file(actualPng, reference, fs::copy_options::overwrite_existing);
    std::cout << "updated reference " << reference << "\n";
    return;
  }
  ASSERT_TRUE(fs::exists(reference)) << reference << " is missing; run with KURAGE_UPDATE_REFERENCES=1";
  const render::Image expected = render::readPng(reference);
  const render::CompareResult result = render::compareImages(actual, expected, options);
  if (!result.passed) {
    const fs::path folder = test::binaryDir() / "test_output" / name;
    fs::create_directories(folder);
    fs::copy_file(actualPng, folder / "new.png", fs::copy_options::overwrite_existing);
    fs::copy_file(reference, folder / "reference.png", fs::copy_options::overwrite_existing);
    if (result.sizesMatch) render::writePng(render::differenceImage(actual, expected, 10.0f), folder / "diff.png");
    ADD_FAILURE() << name << ": " << result.failingFraction * 100 << " % of pixels differ by more than "
                  << options.pixelThreshold << " (allowed " << options.allowedFailingFraction * 100
                  << " %), mean error " << result.meanError << "\n  new image:  " << (folder / "new.png")
                  << "\n  reference:  " << (folder / "reference.png") << "\n  difference: " << (folder / "diff.png");
  }
}

}  // namespace

TEST(EndToEnd, TinyDamBreakThroughAllStages) {
  test::TempDir dir;
  const fs::path out = dir.path() / "out";
  const fs::path scene = test::sourceDir() / "tests/scenes/tiny_dam_break.json";
  ASSERT_EQ(test::runKurage("run " + scene.string() + " -o " + out.string() + " --threads 2", dir.path() / "log.txt"), 0)
      << pipeline::readText(dir.path() / "log.txt");
  for (int f = 0; f <= 4; ++f) {
    EXPECT_TRUE(fs::exists(pipeline::frameFile(out / "particles", f, "vdb"))) << f;
    EXPECT_TRUE(fs::exists(pipeline::frameFile(out / "surfaces", f, "vdb"))) << f;
    EXPECT_TRUE(fs::exists(pipeline::frameFile(out / "frames", f, "png"))) << f;
  }
  for (const auto& entry : fs::recursive_directory_iterator(out))
    EXPECT_NE(entry.path().extension(), ".tmp") << "left behind: " << entry.path();

  const nlohmann::json run = nlohmann::json::parse(pipeline::readText(out / "run.json"));
  for (const char* stage : {"sim", "surface", "render"}) EXPECT_GT(run["stages"][stage]["seconds"], 0.0) << stage;
  EXPECT_EQ(run["parameters"]["fluid"]["pressure_stiffness"], 1000.0);
  EXPECT_EQ(run["parameters"]["fluid"]["viscosity"], 0.3) << "defaults filled in";
  EXPECT_FALSE(run["versions"]["openvdb"].get<std::string>().empty());
  EXPECT_FALSE(run["versions"]["embree"].get<std::string>().empty());
  EXPECT_GT(run["derived"]["fluid_particle_mass_kg"], 0.0);

  const std::string log = pipeline::readText(dir.path() / "log.txt");
  EXPECT_NE(log.find("frames: " + (out / "frames").string()), std::string::npos) << log;

  render::CompareOptions options;
  options.pixelThreshold = 0.02f;
  options.allowedFailingFraction = 0.02f;
  expectMatchesReference(out / "frames/0004.png", "tiny_dam_break_0004", options);
}

TEST(EndToEnd, SingleStageCommandsMatchRun) {
  // `sim`, `surface` and `render` one after the other give the same frame as `run`, and a stage
  // whose input is missing is refused with a message naming the missing file.
  test::TempDir dir;
  const fs::path scene = test::sourceDir() / "tests/scenes/tiny_dam_break.json";
  const fs::path a = dir.path() / "a", b = dir.path() / "b";
  const std::string frames = " --frames 2-2";
  EXPECT_EQ(test::runKurage("surface " + scene.string() + " -o " + b.string() + frames, dir.path() / "l0.txt"), 1);
  EXPECT_NE(pipeline::readText(dir.path() / "l0.txt").find("0002.vdb: missing"), std::string::npos);
  ASSERT_EQ(test::runKurage("run " + scene.string() + " -o " + a.string() + frames, dir.path() / "l1.txt"), 0);
  ASSERT_EQ(test::runKurage("sim " + scene.string() + " -o " + b.string() + frames, dir.path() / "l2.txt"), 0);
  ASSERT_EQ(test::runKurage("surface " + scene.string() + " -o " + b.string() + frames, dir.path() / "l3.txt"), 0);
  ASSERT_EQ(test::runKurage("render " + scene.string() + " -o " + b.string() + frames, dir.path() / "l4.txt"), 0);
  EXPECT_FALSE(fs::exists(a / "frames/0001.png")) << "--frames 2-2 wrote frame 1";
  EXPECT_EQ(pipeline::readText(a / "frames/0002.png"), pipeline::readText(b / "frames/0002.png"));
  // VDB files carry a fresh UUID each, so compare their contents.
  const pipeline::ParticleFrame pa = pipeline::readParticleFrame(a / "particles/0002.vdb");
  const pipeline::ParticleFrame pb = pipeline::readParticleFrame(b / "particles/0002.vdb");
  EXPECT_EQ(pa.px, pb.px);
  EXPECT_EQ(pa.vz, pb.vz);
  EXPECT_EQ(pa.id, pb.id);
}

TEST(EndToEnd, HelpOnEverySubcommand) {
  test::TempDir dir;
  for (const char* command : {"run", "sim", "surface", "render", "check", "schema"}) {
    EXPECT_EQ(test::runKurage(std::string(command) + " --help", dir.path() / "help.txt"), 0) << command;
    EXPECT_NE(pipeline::readText(dir.path() / "help.txt").find("usage: kurage"), std::string::npos) << command;
  }
  EXPECT_EQ(test::runKurage("frobnicate", dir.path() / "bad.txt"), 2);
}
