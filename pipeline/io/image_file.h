// PNG files (frames, stills) through the I/O layer: encoded in memory by render/, written
// atomically by writeFileAtomic.
#pragma once

#include "render/image.h"

#include <filesystem>

namespace kurage::pipeline {

// Writes an sRGB PNG of the given bit depth (8 or 16). Throws naming the path on failure.
void writePng(const render::Image& image, const std::filesystem::path& path, bool withAlpha = false, int bitDepth = 8);

}  // namespace kurage::pipeline
