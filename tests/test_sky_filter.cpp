// The sky filter (render/sky_filter.h) on hand-made buffers: it never averages across an object,
// a normal or a depth edge, leaves unfiltered pixels as they are, keeps the albedo's edges, and
// over a tile on one surface cancels any pattern the interleaved sets leave.
#include "render/image.h"
#include "render/sky_filter.h"

#include <gtest/gtest.h>

#include <Eigen/Core>

#include <cmath>

namespace kr = kurage::render;
using Eigen::Vector3f;

namespace {

constexpr int kSize = 16;

// A deviation per interleaving class (x mod 4, y mod 4) that sums to zero over the 16 classes.
float classPattern(int x, int y) {
  const int c = (x % 4) * 4 + (y % 4);
  return 0.02f * float(c - 7.5f) / 7.5f;
}

// 16 x 16 pixels of one surface (object 3, normal +z, depth 10): sky irradiance e plus the class
// pattern, a checker albedo (0.2 and 0.8 in 2-pixel cells) as the weight.
kr::SkyBuffers plane(float e) {
  kr::SkyBuffers b(kSize, kSize);
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x) {
      const size_t i = size_t(y) * kSize + size_t(x);
      b.weight[i] = Vector3f::Constant(((x / 2 + y / 2) % 2) ? 0.8f : 0.2f);
      b.sky[i] = b.weight[i] * (e + classPattern(x, y));
      b.normal[i] = {0, 0, 1};
      b.depth[i] = 10.0f;
      b.objectId[i] = 3;
    }
  return b;
}

// The image whose colour is the sky term alone.
kr::Image skyImage(const kr::SkyBuffers& b) {
  kr::Image image(b.width, b.height);
  for (int y = 0; y < b.height; ++y)
    for (int x = 0; x < b.width; ++x) {
      const Vector3f s = b.sky[size_t(y) * size_t(b.width) + size_t(x)];
      image.at(x, y) = {s.x(), s.y(), s.z(), 1.0f};
    }
  return image;
}

kr::SkyFilterSettings tile4() {
  kr::SkyFilterSettings s;
  s.enabled = true;
  s.tile = 4;
  return s;
}

// The right half (x >= 8) made different by `change`; every pixel's filtered irradiance must stay
// within its own half's range (0.5 +- 0.02 left, 2.0 +- 0.02 right).
template <class Change>
void expectHalvesApart(Change change) {
  kr::SkyBuffers b = plane(0.5f);
  for (int y = 0; y < kSize; ++y)
    for (int x = kSize / 2; x < kSize; ++x) {
      const size_t i = size_t(y) * kSize + size_t(x);
      b.sky[i] = b.weight[i] * (2.0f + classPattern(x, y));
      change(b, i);
    }
  kr::Image image = skyImage(b);
  kr::filterSky(b, tile4(), image);
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x) {
      const size_t i = size_t(y) * kSize + size_t(x);
      const float e = image.at(x, y).x() / b.weight[i].x();
      const float expected = x < kSize / 2 ? 0.5f : 2.0f;
      ASSERT_NEAR(e, expected, 0.0201f) << "pixel " << x << ", " << y;
    }
}

}  // namespace

TEST(SkyFilter, CancelsTheInterleavedPatternOnOneSurfaceAndKeepsTheAlbedosEdges) {
  // Away from the image's border every window holds each class with equal weight: the pattern
  // cancels, and each pixel is its own albedo times the surface's irradiance.
  const kr::SkyBuffers b = plane(0.5f);
  kr::Image image = skyImage(b);
  kr::filterSky(b, tile4(), image);
  for (int y = 2; y < kSize - 2; ++y)
    for (int x = 2; x < kSize - 2; ++x) {
      const float albedo = b.weight[size_t(y) * kSize + size_t(x)].x();
      ASSERT_NEAR(image.at(x, y).x(), albedo * 0.5f, 1e-6f) << "pixel " << x << ", " << y;
      ASSERT_EQ(image.at(x, y).w(), 1.0f);
    }
}

TEST(SkyFilter, NeverCrossesAnObjectANormalOrADepthEdge) {
  expectHalvesApart([](kr::SkyBuffers& b, size_t i) { b.objectId[i] = 4; });
  expectHalvesApart([](kr::SkyBuffers& b, size_t i) { b.normal[i] = {1, 0, 0}; });
  expectHalvesApart([](kr::SkyBuffers& b, size_t i) { b.depth[i] = 12.0f; });
}

TEST(SkyFilter, LeavesPixelsWithoutAPrimarySurfaceAndDoesNotLendThem) {
  // Every other column has no primary surface (several objects in its samples): those keep
  // their value (here 100 times the rest's), which no other pixel takes up.
  kr::SkyBuffers b = plane(0.5f);
  for (int y = 0; y < kSize; ++y)
    for (int x = 1; x < kSize; x += 2) {
      const size_t i = size_t(y) * kSize + size_t(x);
      b.objectId[i] = kr::kObjectSky;
      b.sky[i] *= 100.0f;
    }
  kr::Image image = skyImage(b);
  kr::filterSky(b, tile4(), image);
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x) {
      const size_t i = size_t(y) * kSize + size_t(x);
      if (x % 2) ASSERT_EQ(image.at(x, y).x(), b.sky[i].x()) << "pixel " << x << ", " << y;
      else ASSERT_NEAR(image.at(x, y).x() / b.weight[i].x(), 0.5f, 0.0201f) << "pixel " << x << ", " << y;
    }
}
