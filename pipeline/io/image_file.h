// PNG files (frames, stills) through the I/O layer: encoded in memory by render/, written
// atomically by writeFileAtomic.
//
// A frame may carry a stamp (stamp.h: stage, scene hash, frame) as a PNG text chunk
// (tEXt "kurage:stamp" = "STAGE HASH FRAME", right after IHDR), so the render stage can tell a
// finished frame made from the same inputs and settings from one it must redo. Image viewers
// ignore the chunk.
#pragma once

#include "pipeline/io/stamp.h"
#include "render/image.h"

#include <filesystem>

namespace kurage::pipeline {

// Writes an sRGB PNG of the given bit depth (8 or 16), with `stamp` when given. Throws naming the
// path on failure.
void writePng(const render::Image& image, const std::filesystem::path& path, bool withAlpha = false, int bitDepth = 8,
              const FileStamp* stamp = nullptr);

// True when `path` is a complete PNG (signature, every chunk's CRC right, IEND last) whose stamp
// equals `expected` in every field. False for a missing, damaged, unstamped or foreign file.
bool pngStampMatches(const std::filesystem::path& path, const FileStamp& expected);

}  // namespace kurage::pipeline
