// Image I/O and comparison: PNG round trips (exact at 8 bit), 16-bit and grey+alpha decoding,
// error reporting, atomic writes, the failing-fraction comparison and the sRGB curve.
#include "pipeline/io/image_file.h"
#include "render/image.h"

#include "test_util.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

namespace kr = kurage::render;
namespace fs = std::filesystem;

namespace {

using kurage::test::TempDir;

std::vector<char> readBytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void writeBytes(const fs::path& path, const std::vector<char>& bytes) {
  std::ofstream out(path, std::ios::binary);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

// Every 8-bit code appears in each channel, in different orders.
kr::Image allCodesImage() {
  kr::Image image(256, 2);
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 256; ++x) {
      const int codes[4] = {x, 255 - x, (x * 7 + y * 31) % 256, (x * 13 + 5) % 256};
      for (int c = 0; c < 3; ++c) image.at(x, y)[c] = kr::srgbToLinear(codes[c] / 255.0f);
      image.at(x, y)[3] = codes[3] / 255.0f;
    }
  return image;
}

template <typename F>
std::string whatOf(F&& f) {
  try {
    f();
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "(no exception)";
}

}  // namespace

TEST(Png, RoundTripIsExactForEightBitSrgbValues) {
  TempDir dir;
  const fs::path file = dir.path() / "codes.png";
  const kr::Image image = allCodesImage();
  kurage::pipeline::writePng(image, file);
  const kr::Image back = kr::readPng(file);
  ASSERT_EQ(back.width(), image.width());
  ASSERT_EQ(back.height(), image.height());
  for (int y = 0; y < image.height(); ++y)
    for (int x = 0; x < image.width(); ++x) {
      for (int c = 0; c < 3; ++c) ASSERT_EQ(back.at(x, y)[c], image.at(x, y)[c]) << x << "," << y << " c" << c;
      ASSERT_EQ(back.at(x, y)[3], 1.0f) << "an RGB PNG reads back opaque";
    }
}

TEST(Png, AlphaRoundTrip) {
  TempDir dir;
  const fs::path file = dir.path() / "alpha.png";
  const kr::Image image = allCodesImage();
  kurage::pipeline::writePng(image, file, /*withAlpha=*/true);
  const kr::Image back = kr::readPng(file);
  for (int y = 0; y < image.height(); ++y)
    for (int x = 0; x < image.width(); ++x)
      for (int c = 0; c < 4; ++c) ASSERT_EQ(back.at(x, y)[c], image.at(x, y)[c]) << x << "," << y << " c" << c;
}

TEST(Png, WriteClampsOutOfRangeValues) {
  TempDir dir;
  const fs::path file = dir.path() / "clamp.png";
  kr::Image image(2, 1);
  image.at(0, 0) = Eigen::Vector4f(-1.0f, 7.0f, 0.0f, 1.0f);
  image.at(1, 0) = Eigen::Vector4f(1.0f, 0.0f, 2.0f, 1.0f);
  kurage::pipeline::writePng(image, file);
  const kr::Image back = kr::readPng(file);
  EXPECT_EQ(back.at(0, 0), Eigen::Vector4f(0.0f, 1.0f, 0.0f, 1.0f));
  EXPECT_EQ(back.at(1, 0), Eigen::Vector4f(1.0f, 0.0f, 1.0f, 1.0f));
}

TEST(Png, ReadsSixteenBitGreyAlpha) {
  // 2x1, 16-bit grey+alpha: (0x8000, 0xFFFF), (0xFFFF, 0x4000); made with Python zlib/struct.
  const unsigned char png[] = {
      0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a, 0x00, 0x00, 0x00, 0x0d, 0x49, 0x48, 0x44, 0x52, 0x00, 0x00,
      0x00, 0x02, 0x00, 0x00, 0x00, 0x01, 0x10, 0x04, 0x00, 0x00, 0x00, 0x0e, 0xbb, 0x6b, 0x42, 0x00, 0x00, 0x00,
      0x0f, 0x49, 0x44, 0x41, 0x54, 0x78, 0x9c, 0x63, 0x68, 0x60, 0xf8, 0x0f, 0x04, 0x0e, 0x0c, 0x00, 0x16, 0x77,
      0x04, 0xbd, 0x7f, 0x59, 0x91, 0xbd, 0x00, 0x00, 0x00, 0x00, 0x49, 0x45, 0x4e, 0x44, 0xae, 0x42, 0x60, 0x82};
  TempDir dir;
  const fs::path file = dir.path() / "grey16.png";
  writeBytes(file, std::vector<char>(std::begin(png), std::end(png)));
  const kr::Image image = kr::readPng(file);
  ASSERT_EQ(image.width(), 2);
  ASSERT_EQ(image.height(), 1);
  const float grey = kr::srgbToLinear(static_cast<float>(0x8000 / 65535.0));
  for (int c = 0; c < 3; ++c) {
    EXPECT_FLOAT_EQ(image.at(0, 0)[c], grey);
    EXPECT_FLOAT_EQ(image.at(1, 0)[c], 1.0f);
  }
  EXPECT_FLOAT_EQ(image.at(0, 0)[3], 1.0f);
  EXPECT_FLOAT_EQ(image.at(1, 0)[3], static_cast<float>(0x4000 / 65535.0));
}

TEST(Png, ReadingMissingFileThrowsNamingThePath) {
  TempDir dir;
  const fs::path file = dir.path() / "does_not_exist.png";
  EXPECT_NE(whatOf([&] { kr::readPng(file); }).find(file.string()), std::string::npos);
}

TEST(Png, ReadingTruncatedFileThrowsNamingThePath) {
  TempDir dir;
  const fs::path good = dir.path() / "good.png";
  kurage::pipeline::writePng(allCodesImage(), good);
  std::vector<char> bytes = readBytes(good);
  ASSERT_GT(bytes.size(), 100u);
  bytes.resize(bytes.size() / 2);
  const fs::path truncated = dir.path() / "truncated.png";
  writeBytes(truncated, bytes);
  EXPECT_NE(whatOf([&] { kr::readPng(truncated); }).find(truncated.string()), std::string::npos);

  const fs::path notPng = dir.path() / "text.png";
  writeBytes(notPng, {'h', 'e', 'l', 'l', 'o', ' ', 'w', 'o', 'r', 'l', 'd'});
  EXPECT_NE(whatOf([&] { kr::readPng(notPng); }).find(notPng.string()), std::string::npos);
}

TEST(Png, WriteLeavesNoTemporaryFileBehind) {
  TempDir dir;
  const fs::path file = dir.path() / "frame.png";
  kurage::pipeline::writePng(kr::Image(4, 3), file);
  kurage::pipeline::writePng(kr::Image(5, 2), file);  // overwriting an existing file works too
  std::vector<fs::path> entries;
  for (const auto& entry : fs::directory_iterator(dir.path())) entries.push_back(entry.path().filename());
  ASSERT_EQ(entries.size(), 1u);
  EXPECT_EQ(entries[0], "frame.png");
  EXPECT_EQ(kr::readPng(file).width(), 5);
}

TEST(Png, WriteIntoMissingDirectoryThrowsNamingThePath) {
  TempDir dir;
  const fs::path file = dir.path() / "no_such_dir" / "frame.png";
  EXPECT_NE(whatOf([&] { kurage::pipeline::writePng(kr::Image(2, 2), file); }).find(file.string()), std::string::npos);
}

TEST(Compare, IdenticalImagesPass) {
  const kr::Image image = allCodesImage();
  const kr::CompareResult result = kr::compareImages(image, image, {});
  EXPECT_TRUE(result.sizesMatch);
  EXPECT_TRUE(result.passed);
  EXPECT_EQ(result.failingFraction, 0.0);
  EXPECT_EQ(result.meanError, 0.0);
  EXPECT_EQ(result.maxError, 0.0);
}

TEST(Compare, OneChangedPixelInHundredIsOnePercent) {
  const kr::Image reference(10, 10, Eigen::Vector4f(0.2f, 0.2f, 0.2f, 1.0f));
  kr::Image actual = reference;
  actual.at(3, 7)[1] += 0.5f;
  const float expectedError = kr::linearToSrgb(0.7f) - kr::linearToSrgb(0.2f);

  kr::CompareOptions onePercent;
  onePercent.allowedFailingFraction = 0.01f;
  const kr::CompareResult result = kr::compareImages(actual, reference, onePercent);
  EXPECT_EQ(result.failingFraction, 0.01);
  EXPECT_TRUE(result.passed);
  EXPECT_NEAR(result.maxError, expectedError, 1e-6);
  EXPECT_NEAR(result.meanError, expectedError / 300.0, 1e-8);

  kr::CompareOptions halfPercent;
  halfPercent.allowedFailingFraction = 0.005f;
  EXPECT_FALSE(kr::compareImages(actual, reference, halfPercent).passed);

  kr::CompareOptions looseThreshold;
  looseThreshold.pixelThreshold = 1.0f;
  looseThreshold.allowedFailingFraction = 0.0f;
  const kr::CompareResult loose = kr::compareImages(actual, reference, looseThreshold);
  EXPECT_EQ(loose.failingFraction, 0.0);
  EXPECT_TRUE(loose.passed);
}

TEST(Compare, SizeMismatchFails) {
  const kr::CompareResult result = kr::compareImages(kr::Image(10, 10), kr::Image(10, 9), {});
  EXPECT_FALSE(result.sizesMatch);
  EXPECT_FALSE(result.passed);
}

TEST(Compare, DifferenceImageShowsScaledSrgbDifference) {
  const kr::Image reference(3, 2, Eigen::Vector4f(0.2f, 0.2f, 0.2f, 1.0f));
  kr::Image actual = reference;
  actual.at(1, 1)[0] = kr::srgbToLinear(kr::linearToSrgb(0.2f) + 0.05f);
  const kr::Image diff = kr::differenceImage(actual, reference, 10.0f);
  EXPECT_NEAR(kr::linearToSrgb(diff.at(1, 1)[0]), 0.5f, 1e-4f);
  EXPECT_EQ(diff.at(1, 1)[1], 0.0f);
  EXPECT_EQ(diff.at(0, 0)[0], 0.0f);
}

TEST(Srgb, KnownValuesAndRoundTrip) {
  EXPECT_NEAR(kr::linearToSrgb(0.5f), 0.735357f, 1e-5f);
  EXPECT_NEAR(kr::srgbToLinear(0.5f), 0.214041f, 1e-5f);
  EXPECT_EQ(kr::linearToSrgb(0.0f), 0.0f);
  EXPECT_NEAR(kr::linearToSrgb(1.0f), 1.0f, 1e-6f);
  EXPECT_NEAR(kr::linearToSrgb(0.002f), 12.92f * 0.002f, 1e-7f);  // linear segment
  for (int i = 0; i <= 1000; ++i) {
    const float v = i / 1000.0f;
    ASSERT_NEAR(kr::srgbToLinear(kr::linearToSrgb(v)), v, 2e-6f) << v;
    ASSERT_NEAR(kr::linearToSrgb(kr::srgbToLinear(v)), v, 2e-6f) << v;
  }
}
