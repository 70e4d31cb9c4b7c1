// PNG files (frames, plots, stills) through the I/O layer: encoded in memory by render/, written
// atomically by writeFileAtomic.
#pragma once

#include "render/image.h"
#include "render/plot.h"

#include <filesystem>

namespace kurage::pipeline {

// Writes an sRGB PNG of the given bit depth (8 or 16). Throws naming the path on failure.
void writePng(const render::Image& image, const std::filesystem::path& path, bool withAlpha = false, int bitDepth = 8);

// Renders the plot and writes it as an 8-bit PNG.
void writePlotPng(const render::Plot& plot, const std::filesystem::path& path);

}  // namespace kurage::pipeline
