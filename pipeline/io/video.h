// Frames to an MP4 with the Debian `ffmpeg` program (H.264, yuv420p, the scene's fps), written
// through pipeline/io (a unique temporary, checked, renamed). Without ffmpeg on the PATH the frames stay and the caller
// prints the command that would encode them.
#pragma once

#include "pipeline/io/process.h"

#include <filesystem>
#include <string>
#include <vector>

namespace kurage::pipeline {

struct VideoResult {
  bool encoded = false;     // the movie was written
  bool upToDate = false;    // the movie was already there, whole and with the same stamp: kept
  std::string command;      // the ffmpeg command line (for the message when ffmpeg is missing)
};

// Encodes frames NNNN.png first .. first+count-1 of `framesFolder` into `movie` at `fps`.
// Returns encoded = false (and the command) when ffmpeg is not on the PATH; throws
// std::runtime_error if ffmpeg fails (the temporary file is removed).
// `stamp` (e.g. "video RENDERHASH FIRST COUNT FPS") goes into the movie's comment tag; a movie that
// ffprobe reads whole, with `count` frames and this stamp, is kept (upToDate) unless `force`.
// `stop` returning true ends ffmpeg (runProgram) and throws IoError; no movie is left.
VideoResult encodeVideo(const std::filesystem::path& framesFolder, int first, int count, double fps,
                        const std::filesystem::path& movie, const std::string& stamp = "", bool force = false,
                        const StopRequested& stop = {});

// Encodes and prints "video: PATH", or a line saying how to encode the frames.
void encodeVideoAndReport(const std::filesystem::path& framesFolder, int first, int count, double fps,
                          const std::filesystem::path& movie, const std::string& stamp = "", bool force = false,
                          const StopRequested& stop = {});

// True if an executable named `program` is on the PATH.
bool onPath(const std::string& program);

}  // namespace kurage::pipeline
