// Image storage, PNG I/O (libpng) and image comparison; see image.h.
//
// Writing uses libpng's simplified API (png_image_write_to_file), which reports errors in
// png_image::message instead of longjmp. Reading uses the classic API because it keeps 16-bit
// samples and does not premultiply alpha; its error longjmp lands in readPngRows, which owns
// no C++ objects, so no destructor is ever skipped.
#include "render/image.h"

#include <png.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <stdexcept>
#include <system_error>

namespace kurage::render {

Image::Image(int width, int height, const Eigen::Vector4f& fill) : width_(width), height_(height) {
  if (width < 0 || height < 0) throw std::invalid_argument("Image: negative size");
  pixels_.assign(static_cast<size_t>(width) * static_cast<size_t>(height), fill);
}

namespace {

// Clamps to [0,1]; NaN becomes 0.
double clamp01(double v) { return v > 0.0 ? std::min(v, 1.0) : 0.0; }

png_byte toByte(double v) { return static_cast<png_byte>(std::lround(clamp01(v) * 255.0)); }

// "'path'" (built by appending: GCC 12 gives a false -Wrestrict for "'" + std::string).
std::string quoted(const std::filesystem::path& path) {
  std::string text(1, '\'');
  text += path.string();
  text += '\'';
  return text;
}

}  // namespace

// IEC 61966-2-1 sRGB transfer function (exact piecewise curve, not a 2.2 power).
float linearToSrgb(float linear) {
  const double v = clamp01(linear);
  return static_cast<float>(v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1.0 / 2.4) - 0.055);
}

float srgbToLinear(float encoded) {
  const double v = clamp01(encoded);
  return static_cast<float>(v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4));
}

namespace {

std::string encodePng8(const Image& image, bool withAlpha) {
  const int channels = withAlpha ? 4 : 3;
  std::vector<png_byte> bytes(static_cast<size_t>(image.width()) * image.height() * channels);
  size_t i = 0;
  for (int y = 0; y < image.height(); ++y)
    for (int x = 0; x < image.width(); ++x) {
      const Eigen::Vector4f& p = image.at(x, y);
      for (int c = 0; c < 3; ++c) bytes[i++] = toByte(linearToSrgb(p[c]));
      if (withAlpha) bytes[i++] = toByte(p[3]);  // alpha is stored linearly
    }

  png_image png{};
  png.version = PNG_IMAGE_VERSION;
  png.width = static_cast<png_uint_32>(image.width());
  png.height = static_cast<png_uint_32>(image.height());
  png.format = withAlpha ? PNG_FORMAT_RGBA : PNG_FORMAT_RGB;  // 8-bit, tagged sRGB
  png_alloc_size_t size = 0;
  bool ok = png_image_write_to_memory(&png, nullptr, &size, 0, bytes.data(), 0, nullptr) != 0;
  std::string out(ok ? size : 0, '\0');
  if (ok) ok = png_image_write_to_memory(&png, out.data(), &size, 0, bytes.data(), 0, nullptr) != 0;
  const std::string message = png.message;
  png_image_free(&png);
  if (!ok) throw std::runtime_error("encodePng: " + message);
  out.resize(size);
  return out;
}

}  // namespace

namespace {

struct PngError {
  char message[256] = "unknown libpng error";
};

void onPngError(png_structp png, png_const_charp message) {
  auto* error = static_cast<PngError*>(png_get_error_ptr(png));
  std::snprintf(error->message, sizeof error->message, "%s", message);
  png_longjmp(png, 1);
}

void onPngWarning(png_structp, png_const_charp) {}

// Decoded 8- or 16-bit (big-endian) RGBA rows; owned by the caller of readPngRows so that
// a longjmp out of libpng never skips a destructor.
struct PngRows {
  int width = 0, height = 0, bitDepth = 0;
  std::vector<png_byte> bytes;
  std::vector<png_bytep> rows;
};

// Decodes the whole file into `out`. Returns false after a libpng error (message in the
// error pointer). Only the caller's objects are modified after setjmp.
bool readPngRows(png_structp png, png_infop info, std::FILE* file, PngRows& out) {
  if (setjmp(png_jmpbuf(png))) return false;
  png_init_io(png, file);
  png_read_info(png, info);
  png_set_expand(png);  // palette -> RGB, grey < 8 bit -> 8 bit, tRNS -> alpha
  png_set_gray_to_rgb(png);
  if (!(png_get_color_type(png, info) & PNG_COLOR_MASK_ALPHA) && !png_get_valid(png, info, PNG_INFO_tRNS))
    png_set_add_alpha(png, 0xffff, PNG_FILLER_AFTER);  // opaque; truncated to 0xff at 8 bit
  png_set_interlace_handling(png);
  png_read_update_info(png, info);
  if (png_get_channels(png, info) != 4) png_error(png, "unexpected channel count after expansion");
  out.width = static_cast<int>(png_get_image_width(png, info));
  out.height = static_cast<int>(png_get_image_height(png, info));
  out.bitDepth = png_get_bit_depth(png, info);
  const size_t rowBytes = png_get_rowbytes(png, info);
  out.bytes.resize(rowBytes * static_cast<size_t>(out.height));
  out.rows.resize(static_cast<size_t>(out.height));
  for (int y = 0; y < out.height; ++y) out.rows[static_cast<size_t>(y)] = out.bytes.data() + rowBytes * y;
  png_read_image(png, out.rows.data());
  png_read_end(png, nullptr);
  return true;
}

}  // namespace

Image readPng(const std::filesystem::path& path) {
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> file(std::fopen(path.c_str(), "rb"), &std::fclose);
  if (!file) throw std::runtime_error("readPng " + quoted(path) + ": cannot open file");
  png_byte signature[8] = {};
  if (std::fread(signature, 1, 8, file.get()) != 8 || png_sig_cmp(signature, 0, 8) != 0)
    throw std::runtime_error("readPng " + quoted(path) + ": not a PNG file");
  std::rewind(file.get());

  PngError error;
  png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &error, onPngError, onPngWarning);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  PngRows decoded;
  const bool ok = info && readPngRows(png, info, file.get(), decoded);
  png_destroy_read_struct(&png, &info, nullptr);
  if (!ok) throw std::runtime_error("readPng " + quoted(path) + ": " + error.message);

  // Colour samples are sRGB-encoded; alpha is linear.
  Image image(decoded.width, decoded.height);
  const double maxValue = decoded.bitDepth == 16 ? 65535.0 : 255.0;
  for (int y = 0; y < decoded.height; ++y) {
    const png_byte* row = decoded.rows[static_cast<size_t>(y)];
    for (int x = 0; x < decoded.width; ++x)
      for (int c = 0; c < 4; ++c) {
        const int v = decoded.bitDepth == 16 ? (row[(4 * x + c) * 2] << 8) | row[(4 * x + c) * 2 + 1]
                                             : row[4 * x + c];
        const float f = static_cast<float>(v / maxValue);
        image.at(x, y)[c] = c < 3 ? srgbToLinear(f) : f;
      }
  }
  return image;
}

namespace {

// libpng's write callback: appends to the std::string behind the io pointer.
void appendToString(png_structp png, png_bytep data, png_size_t length) {
  auto* out = static_cast<std::string*>(png_get_io_ptr(png));
  try {
    out->append(reinterpret_cast<const char*>(data), length);
  } catch (...) {
    png_error(png, "out of memory");
  }
}

void flushNothing(png_structp) {}

// Encodes 16-bit big-endian rows into `out`. Returns false after a libpng error (message in the
// error pointer). Owns no C++ objects, so libpng's longjmp skips no destructor.
bool writePngRows16(png_structp png, png_infop info, std::string* out, int width, int height, bool withAlpha,
                    png_bytep* rows) {
  if (setjmp(png_jmpbuf(png))) return false;
  png_set_write_fn(png, out, appendToString, flushNothing);
  png_set_IHDR(png, info, static_cast<png_uint_32>(width), static_cast<png_uint_32>(height), 16,
               withAlpha ? PNG_COLOR_TYPE_RGBA : PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
               PNG_FILTER_TYPE_DEFAULT);
  png_set_sRGB_gAMA_and_cHRM(png, info, PNG_sRGB_INTENT_PERCEPTUAL);
  png_write_info(png, info);
  png_write_image(png, rows);
  png_write_end(png, nullptr);
  return true;
}

}  // namespace

std::string encodePng(const Image& image, bool withAlpha, int bitDepth) {
  if (bitDepth != 8 && bitDepth != 16) throw std::invalid_argument("encodePng: bit depth must be 8 or 16");
  if (image.width() <= 0 || image.height() <= 0) throw std::runtime_error("encodePng: empty image");
  if (bitDepth == 8) return encodePng8(image, withAlpha);
  const int channels = withAlpha ? 4 : 3;
  const size_t rowBytes = static_cast<size_t>(image.width()) * channels * 2;
  std::vector<png_byte> bytes(rowBytes * static_cast<size_t>(image.height()));
  std::vector<png_bytep> rows(static_cast<size_t>(image.height()));
  for (int y = 0; y < image.height(); ++y) {
    png_byte* row = bytes.data() + rowBytes * static_cast<size_t>(y);
    rows[static_cast<size_t>(y)] = row;
    for (int x = 0; x < image.width(); ++x)
      for (int c = 0; c < channels; ++c) {
        const float p = image.at(x, y)[c];
        const auto v = static_cast<unsigned>(std::lround(clamp01(c < 3 ? linearToSrgb(p) : p) * 65535.0));
        row[(x * channels + c) * 2] = static_cast<png_byte>(v >> 8);
        row[(x * channels + c) * 2 + 1] = static_cast<png_byte>(v & 0xFF);
      }
  }
  std::string out;
  PngError error;
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &error, onPngError, onPngWarning);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  const bool ok = info && writePngRows16(png, info, &out, image.width(), image.height(), withAlpha, rows.data());
  png_destroy_write_struct(&png, &info);
  if (!ok) throw std::runtime_error(std::string("encodePng: ") + error.message);
  return out;
}

CompareResult compareImages(const Image& actual, const Image& reference, const CompareOptions& options) {
  CompareResult result;
  result.sizesMatch = actual.width() == reference.width() && actual.height() == reference.height();
  if (!result.sizesMatch) return result;
  const size_t pixels = static_cast<size_t>(actual.width()) * actual.height();
  if (pixels == 0) {
    result.failingFraction = 0.0;
    result.passed = true;
    return result;
  }
  size_t failing = 0;
  double sum = 0.0;
  for (int y = 0; y < actual.height(); ++y)
    for (int x = 0; x < actual.width(); ++x) {
      double worst = 0.0;
      for (int c = 0; c < 3; ++c) {
        const double d = std::abs(double(linearToSrgb(actual.at(x, y)[c])) - linearToSrgb(reference.at(x, y)[c]));
        sum += d;
        worst = std::max(worst, d);
      }
      result.maxError = std::max(result.maxError, worst);
      if (worst > options.pixelThreshold) ++failing;
    }
  result.failingFraction = static_cast<double>(failing) / static_cast<double>(pixels);
  result.meanError = sum / (3.0 * static_cast<double>(pixels));
  // The allowed fraction is a float (0.01f < 0.01): allow for its rounding so that exactly
  // 1 % failing passes at 1 %.
  result.passed = result.failingFraction <= double(options.allowedFailingFraction) * (1.0 + 1e-6);
  return result;
}

Image differenceImage(const Image& actual, const Image& reference, float gain) {
  if (actual.width() != reference.width() || actual.height() != reference.height())
    throw std::invalid_argument("differenceImage: image sizes differ");
  Image diff(actual.width(), actual.height());
  for (int y = 0; y < actual.height(); ++y)
    for (int x = 0; x < actual.width(); ++x)
      for (int c = 0; c < 3; ++c) {
        const float d = std::abs(linearToSrgb(actual.at(x, y)[c]) - linearToSrgb(reference.at(x, y)[c]));
        // Stored linear so that the written PNG shows gain * |difference| as its sRGB value.
        diff.at(x, y)[c] = srgbToLinear(gain * d);
      }
  return diff;
}

double imageRmse(const Image& actual, const Image& reference) {
  if (actual.width() != reference.width() || actual.height() != reference.height())
    throw std::invalid_argument("imageRmse: the images differ in size");
  const size_t pixels = size_t(actual.width()) * size_t(actual.height());
  if (pixels == 0) return 0.0;
  double sum = 0.0;
  for (int y = 0; y < actual.height(); ++y)
    for (int x = 0; x < actual.width(); ++x)
      for (int c = 0; c < 3; ++c) {
        const double a = linearToSrgb(std::clamp(actual.at(x, y)[c], 0.0f, 1.0f));
        const double b = linearToSrgb(std::clamp(reference.at(x, y)[c], 0.0f, 1.0f));
        sum += (a - b) * (a - b);
      }
  return std::sqrt(sum / (3.0 * double(pixels)));
}

}  // namespace kurage::render
