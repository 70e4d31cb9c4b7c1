// Images: linear float RGBA pixels, PNG input/output, and the image comparison the
// image-diff tests use (per-pixel threshold plus an allowed failing fraction, as in
// Blender's render tests).
//
// Pixel values are linear radiance in [0, inf); writePng applies the sRGB transfer
// function and clamps to [0, 1]. readPng returns values in [0, 1] decoded back to linear.
// Rows are stored top-down (row 0 is the top of the picture).
#pragma once

#include <Eigen/Core>

#include <filesystem>
#include <string>
#include <vector>

namespace kurage::render {

class Image {
public:
  Image() = default;
  Image(int width, int height, const Eigen::Vector4f& fill = Eigen::Vector4f(0, 0, 0, 1));

  int width() const { return width_; }
  int height() const { return height_; }
  Eigen::Vector4f& at(int x, int y) { return pixels_[static_cast<size_t>(y) * width_ + x]; }
  const Eigen::Vector4f& at(int x, int y) const { return pixels_[static_cast<size_t>(y) * width_ + x]; }
  bool operator==(const Image&) const = default;  // same size and pixels (NaN never equal)

private:
  int width_ = 0;
  int height_ = 0;
  std::vector<Eigen::Vector4f> pixels_;
};

// Encodes a PNG in memory with the given bit depth (8 or 16; sRGB-encoded samples either way,
// alpha linear; RGB, or RGBA when withAlpha). Files are written by pipeline/io (writePng there),
// atomically. Throws std::runtime_error for an empty image or a libpng error.
std::string encodePng(const Image& image, bool withAlpha = false, int bitDepth = 8);

// Reads an 8- or 16-bit PNG (grey, grey+alpha, RGB, RGBA). Throws std::runtime_error naming
// the path if the file is missing or not a PNG.
Image readPng(const std::filesystem::path& path);

struct CompareOptions {
  // A pixel fails when any of its RGB channels (sRGB-encoded, in [0,1]) differs by more.
  float pixelThreshold = 0.016f;
  // The comparison passes when at most this fraction of pixels fail.
  float allowedFailingFraction = 0.01f;
};

struct CompareResult {
  bool sizesMatch = false;
  double failingFraction = 1.0;  // fraction of pixels above the threshold
  double meanError = 0.0;        // mean absolute sRGB difference over pixels and channels
  double maxError = 0.0;
  bool passed = false;
};

// Compares two images in sRGB-encoded values (what a person sees, what PNG stores).
CompareResult compareImages(const Image& actual, const Image& reference, const CompareOptions& options);

// |actual - reference| per channel (sRGB-encoded), multiplied by `gain`, as a viewable image.
Image differenceImage(const Image& actual, const Image& reference, float gain = 10.0f);

// Root mean square difference of the RGB channels in sRGB-encoded values (clamped to [0, 1], as
// PNG stores them), over every pixel: what the render studies and benchmarks measure. Throws
// std::invalid_argument when the sizes differ.
double imageRmse(const Image& actual, const Image& reference);

// sRGB transfer function and its inverse, for values in [0,1].
float linearToSrgb(float linear);
float srgbToLinear(float encoded);

}  // namespace kurage::render
