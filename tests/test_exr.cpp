// OpenEXR frames for compositing (pipeline/io/exr.h): every layer reads back (half precision for
// colour, normals and albedo; depth and object id exact), with the frame's time and index.
#include "pipeline/io/exr.h"

#include "test_util.h"

#include <gtest/gtest.h>

#include <cmath>

namespace kurage::pipeline {
namespace {

TEST(Exr, EveryLayerReadsBack) {
  test::TempDir dir;
  const int w = 7, h = 5;
  render::Image beauty(w, h);
  render::FrameLayers layers(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      beauty.at(x, y) = Eigen::Vector4f(0.1f * float(x), 2.5f * float(y), 17.0f, (x + y) % 2 ? 1.0f : 0.0f);
      const size_t i = layers.index(x, y);
      layers.depth[i] = x == 0 ? std::numeric_limits<float>::infinity() : 1.0f + 0.37f * float(x * y);
      layers.normal[i] = Eigen::Vector3f(float(x), 1.0f, float(y)).normalized();
      layers.albedo[i] = Eigen::Vector3f(0.25f, 0.5f, float(x) / float(w));
      layers.objectId[i] = uint32_t(x == 0 ? 0 : 1 + (x + 3 * y) % 4);
    }
  const auto path = dir.path() / "f.exr";
  writeExr(path, beauty, &layers, 2.25, 54);
  EXPECT_FALSE(std::filesystem::exists(dir.path() / "f.exr.tmp"));
  const ExrFrame back = readExr(path);
  ASSERT_TRUE(back.hasLayers);
  EXPECT_EQ(back.time, 2.25);
  EXPECT_EQ(back.frame, 54);
  ASSERT_EQ(back.beauty.width(), w);
  ASSERT_EQ(back.beauty.height(), h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const size_t i = layers.index(x, y);
      for (int c = 0; c < 4; ++c)  // half: 11 significant bits
        EXPECT_NEAR(back.beauty.at(x, y)[c], beauty.at(x, y)[c], 1e-3f * std::max(1.0f, std::abs(beauty.at(x, y)[c])));
      EXPECT_EQ(back.layers.depth[i], layers.depth[i]);
      EXPECT_EQ(back.layers.objectId[i], layers.objectId[i]);
      EXPECT_LT((back.layers.normal[i] - layers.normal[i]).norm(), 2e-3f);
      EXPECT_LT((back.layers.albedo[i] - layers.albedo[i]).norm(), 2e-3f);
    }
}

TEST(Exr, BeautyAloneAndErrorsNameTheFile) {
  test::TempDir dir;
  render::Image beauty(3, 2, Eigen::Vector4f(0.5f, 0.25f, 0.125f, 1.0f));
  writeExr(dir.path() / "b.exr", beauty, nullptr, 0.0, 0);
  const ExrFrame back = readExr(dir.path() / "b.exr");
  EXPECT_FALSE(back.hasLayers);
  EXPECT_EQ(back.beauty.at(2, 1), beauty.at(2, 1));
  try {
    readExr(dir.path() / "missing.exr");
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("missing.exr"), std::string::npos);
  }
  render::FrameLayers wrong(2, 2);
  EXPECT_THROW(writeExr(dir.path() / "w.exr", beauty, &wrong, 0.0, 0), std::invalid_argument);
}

}  // namespace
}  // namespace kurage::pipeline
