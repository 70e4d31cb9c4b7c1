#include "pipeline/io/image_file.h"

#include "pipeline/io/files.h"

namespace kurage::pipeline {

void writePng(const render::Image& image, const std::filesystem::path& path, bool withAlpha, int bitDepth) {
  std::string bytes;
  try {
    bytes = render::encodePng(image, withAlpha, bitDepth);
  } catch (const std::exception& e) {
    throw IoError(path.string() + ": " + e.what());
  }
  writeFileAtomic(path, bytes);
}

}  // namespace kurage::pipeline
