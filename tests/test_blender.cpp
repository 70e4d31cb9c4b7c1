// The Blender importer (assets/blender/import_kurage.py) run headless in Blender 3.4 (Debian's,
// installed by .ci/install-deps): it loads a kurage run's exports, camera, sun and materials and
// renders a frame that is not empty, and its silhouette of the surfaces matches kurage's own
// frame (the camera, the meshes and the frame mapping agree).
#include "render/image.h"

#include "test_util.h"

#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>

namespace kurage {
namespace {

namespace fs = std::filesystem;

std::string slurp(const fs::path& path) {
  std::ifstream in(path);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

int runBlender(const std::string& arguments, const fs::path& log) {
  const std::string command = "blender -b --factory-startup --python " +
                              (test::sourceDir() / "assets/blender/import_kurage.py").string() + " -- " + arguments +
                              " > " + log.string() + " 2>&1";
  const int status = std::system(command.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

class BlenderImport : public ::testing::Test {
protected:
  // Frame 2 of the tiny jellyfish (t = 1/3 s), its surfaces exported as PLY and its chains as OBJ.
  static void SetUpTestSuite() {
    dir_ = new test::TempDir;
    const fs::path scene = test::sourceDir() / "tests/scenes/tiny_jellyfish.json";
    const std::string out = (dir_->path() / "out").string();
    ok_ = test::runKurage("sim " + scene.string() + " -o " + out + " --frames 2-2", dir_->path() / "l1.txt") == 0 &&
          test::runKurage("surface " + scene.string() + " -o " + out + " --frames 2-2", dir_->path() / "l2.txt") == 0 &&
          test::runKurage("export " + out + " --format mesh_ply,chains_obj --frames 2-2", dir_->path() / "l3.txt") == 0;
  }
  static void TearDownTestSuite() { delete dir_; }
  static inline test::TempDir* dir_ = nullptr;
  static inline bool ok_ = false;
};

TEST_F(BlenderImport, RendersTheRunsFrameWithItsLightAndMaterials) {
  ASSERT_TRUE(ok_);
  const fs::path png = dir_->path() / "blender.png";
  ASSERT_EQ(runBlender("--run " + (dir_->path() / "out").string() + " --frame 2 --samples 4 --render " + png.string(),
                       dir_->path() / "blender.txt"),
            0)
      << slurp(dir_->path() / "blender.txt");
  const render::Image image = render::readPng(png);
  // kurage's resolution (80x80) and a lit picture: bright sky and sunlit parts, dark shadows.
  ASSERT_EQ(image.width(), 80);
  ASSERT_EQ(image.height(), 80);
  float brightest = 0.0f, darkest = 1.0f;
  for (int y = 0; y < image.height(); ++y)
    for (int x = 0; x < image.width(); ++x) {
      const float luminance = image.at(x, y).head<3>().mean();
      brightest = std::max(brightest, luminance);
      darkest = std::min(darkest, luminance);
    }
  EXPECT_GT(brightest, 0.3f);
  EXPECT_GT(brightest - darkest, 0.2f);
}

TEST_F(BlenderImport, SilhouetteMatchesKuragesFrame) {
  ASSERT_TRUE(ok_);
  // kurage's frame of the surfaces alone: no ground, no tank, transparent background.
  nlohmann::json scene = nlohmann::json::parse(slurp(test::sourceDir() / "tests/scenes/tiny_jellyfish.json"));
  scene["render"]["ground"]["enabled"] = false;
  scene["render"]["tank"]["enabled"] = false;
  scene["render"]["transparent_background"] = true;
  const fs::path sceneFile = dir_->path() / "surfaces_only.json";
  std::ofstream(sceneFile) << scene.dump(1);
  const fs::path ours = dir_->path() / "kurage.png", theirs = dir_->path() / "blender.png";
  ASSERT_EQ(test::runKurage("still " + sceneFile.string() + " --from " + (dir_->path() / "out").string() +
                                " --time 0.3333333 --spp 4 --width 160 --height 160 -o " + ours.string(),
                            dir_->path() / "still.txt"),
            0)
      << slurp(dir_->path() / "still.txt");
  ASSERT_EQ(runBlender("--run " + (dir_->path() / "out").string() +
                           " --frame 2 --samples 1 --surfaces-only --width 160 --height 160 --render " + theirs.string(),
                       dir_->path() / "blender.txt"),
            0)
      << slurp(dir_->path() / "blender.txt");
  const render::Image a = render::readPng(ours), b = render::readPng(theirs);
  ASSERT_EQ(a.width(), b.width());
  ASSERT_EQ(a.height(), b.height());
  int both = 0, either = 0, inA = 0;
  for (int y = 0; y < a.height(); ++y)
    for (int x = 0; x < a.width(); ++x) {
      const bool sa = a.at(x, y).w() > 0.5f, sb = b.at(x, y).w() > 0.5f;
      both += sa && sb;
      either += sa || sb;
      inA += sa;
    }
  // The surfaces cover a good part of the frame, and the two silhouettes overlap almost entirely
  // (intersection over union: 0.999 when written).
  EXPECT_GT(inA, a.width() * a.height() / 5);
  EXPECT_GT(double(both) / double(either), 0.95) << both << " of " << either;
}

}  // namespace
}  // namespace kurage
