// assets/: the material presets are valid materials for any scene slot, and the sky we ship is
// what its generator says (bit for bit), oriented as kurage reads environment images: bright
// around the default scenes' sun, blue overhead, ground below the horizon.
#include "pipeline/io/files.h"
#include "pipeline/scene.h"
#include "render/image.h"
#include "render/lights.h"

#include "test_util.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

namespace kurage {
namespace {

namespace fs = std::filesystem;

TEST(Assets, EveryMaterialPresetIsAValidMaterialInEverySlot) {
  const nlohmann::json base =
      nlohmann::json::parse(pipeline::readText(test::sourceDir() / "tests/scenes/tiny_jellyfish.json"));
  int presets = 0;
  for (const auto& entry : fs::directory_iterator(test::sourceDir() / "assets/materials")) {
    if (entry.path().extension() != ".json") continue;
    ++presets;
    const nlohmann::json material = nlohmann::json::parse(pipeline::readText(entry.path()));
    for (const char* slot : {"fluid_material", "body_material", "chain_material"}) {
      nlohmann::json scene = base;
      scene["render"][slot] = material;
      EXPECT_NO_THROW(pipeline::parseScene(scene, entry.path().string())) << entry.path() << " as " << slot;
    }
  }
  EXPECT_GE(presets, 5);
}

TEST(Assets, SkyIsWhatItsGeneratorMakes) {
  test::TempDir dir;
  const fs::path made = dir.path() / "sky.png";
  const std::string command = "python3 " + (test::sourceDir() / "assets/skies/make_sky.py").string() + " " +
                              made.string() + " > " + (dir.path() / "log.txt").string() + " 2>&1";
  ASSERT_EQ(std::system(command.c_str()), 0) << pipeline::readText(dir.path() / "log.txt");
  EXPECT_EQ(pipeline::readText(made), pipeline::readText(test::sourceDir() / "assets/skies/clear_day.png"))
      << "assets/skies/clear_day.png is stale: run python3 assets/skies/make_sky.py";
}

TEST(Assets, SkyIsOrientedAsKurageReadsIt) {
  render::Environment sky;
  sky.type = render::EnvironmentType::Image;
  sky.image = std::make_shared<const render::Image>(render::readPng(test::sourceDir() / "assets/skies/clear_day.png"));
  ASSERT_EQ(sky.image->width(), 2 * sky.image->height());
  auto radiance = [&](const Eigen::Vector3f& d) { return render::environmentRadiance(sky, d.normalized()); };
  // The default scenes' sun shines along (-0.4, 0.6, -1): the glow is where it comes from.
  const Eigen::Vector3f towardsSun(0.4f, -0.6f, 1.0f), awayFromSun(-0.4f, 0.6f, 1.0f);
  EXPECT_GT(radiance(towardsSun).sum(), 1.3f * radiance(awayFromSun).sum());
  const Eigen::Vector3f up = radiance(Eigen::Vector3f(0.1f, 0.1f, 1.0f));
  EXPECT_GT(up.z(), 1.5f * up.x()) << "blue overhead";
  const Eigen::Vector3f ground = radiance(Eigen::Vector3f(1.0f, 0.3f, -0.5f));
  EXPECT_LT(ground.sum(), 0.5f * up.sum());
  EXPECT_NEAR(ground.x(), ground.z(), 0.05f) << "a grey-brown ground, not sky";
}

}  // namespace
}  // namespace kurage
