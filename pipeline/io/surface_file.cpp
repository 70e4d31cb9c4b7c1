#include "pipeline/io/surface_file.h"

#include "pipeline/io/files.h"

#include <sstream>

namespace kurage::pipeline {

void writeSurfaceFile(const std::filesystem::path& path, const std::map<std::string, const render::LevelSet*>& grids,
                      double time, int frame, const std::string& sceneHash) {
  render::LevelSetFileInfo info;
  info.time = time;
  info.frame = frame;
  info.tags = {{"kurage:stage", "surface"},
               {"kurage:scene_hash", sceneHash},
               {"kurage:checksum", std::string(kChecksumPlaceholder)}};
  std::ostringstream out;
  try {
    render::writeLevelSets(out, grids, info);
  } catch (const std::exception& e) {
    throw IoError(path.string() + ": cannot serialise the level sets: " + e.what());
  }
  writeSealed(path, std::move(out).str());
}

std::map<std::string, render::LevelSet> readSurfaceFile(const std::filesystem::path& path, const FileStamp& expected,
                                                        render::LevelSetFileInfo* info) {
  std::istringstream in(readVerified(path));
  render::LevelSetFileInfo found;
  std::map<std::string, render::LevelSet> grids;
  try {
    grids = render::readLevelSets(in, &found);
  } catch (const std::exception& e) {
    throw IoError(path.string() + ": cannot parse the level sets: " + e.what());
  }
  const auto tag = [&found](const char* key) {
    const auto it = found.tags.find(key);
    return it == found.tags.end() ? std::string("(none)") : it->second;
  };
  checkStamp({tag("kurage:stage"), tag("kurage:scene_hash"), found.frame}, expected, path);
  if (info) *info = std::move(found);
  return grids;
}

}  // namespace kurage::pipeline
