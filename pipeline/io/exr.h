// Frames for compositing: OpenEXR (scanline, ZIP-compressed) with the layers compositors expect,
// written atomically:
//   R G B A                the beauty pass, linear (not sRGB), half float; A = coverage
//   depth.Z                FrameLayers::depth, float (+inf where the ray meets nothing)
//   normal.X normal.Y normal.Z   world-space normals, half
//   albedo.R albedo.G albedo.B   half
//   object_id              FrameLayers::objectId, uint
// plus the header attributes kurage:time (double, seconds), kurage:frame (int) and, with layers
// whose objectNames are given, kurage:object_names (string vector: the name of object id i at i).
#pragma once

#include "pipeline/io/stamp.h"
#include "render/frame_layers.h"
#include "render/image.h"

#include <filesystem>

namespace kurage::pipeline {

// Writes `beauty` (and the layers, when given; they must match its size). Throws
// std::runtime_error naming the path on failure.
// With `stamp`, the header also carries kurage:stamp ("STAGE HASH FRAME", as image_file.h).
void writeExr(const std::filesystem::path& path, const render::Image& beauty, const render::FrameLayers* layers,
              double time, int frame, const FileStamp* stamp = nullptr);

// Reads back what writeExr wrote (for tests and tools): the beauty pass and, when present, the
// layers. Throws std::runtime_error naming the path.
struct ExrFrame {
  render::Image beauty;
  render::FrameLayers layers;
  bool hasLayers = false;
  double time = 0.0;
  int frame = 0;
  std::string stamp;  // kurage:stamp, empty if none
};
ExrFrame readExr(const std::filesystem::path& path);

// True when `path` reads back whole and carries exactly this stamp.
bool exrStampMatches(const std::filesystem::path& path, const FileStamp& expected);

}  // namespace kurage::pipeline
