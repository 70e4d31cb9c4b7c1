// Surface files OUT/surfaces/NNNN.vdb: the level sets of one frame (render::writeLevelSets'
// OpenVDB stream format) stamped and checksummed as pipeline/io/stamp.h describes.
#pragma once

#include "pipeline/io/stamp.h"
#include "render/surfacing.h"

#include <filesystem>
#include <map>
#include <string>

namespace kurage::pipeline {

// Writes the level sets with kurage:stage "surface", the scene hash, the frame and time, and the
// checksum. Throws IoError naming the path.
void writeSurfaceFile(const std::filesystem::path& path, const std::map<std::string, const render::LevelSet*>& grids,
                      double time, int frame, const std::string& sceneHash);

// Reads a surface file after checking its checksum, then its stamp against `expected` (fields left
// empty are not checked). Throws IoError naming the path for a missing, damaged, foreign or
// wrong-type file. *info receives the metadata when not null.
std::map<std::string, render::LevelSet> readSurfaceFile(const std::filesystem::path& path,
                                                        const FileStamp& expected = {"surface", "", -1},
                                                        render::LevelSetFileInfo* info = nullptr);

}  // namespace kurage::pipeline
