#include "pipeline/video.h"

#include "pipeline/files.h"

#include <cstdio>
#include <cstdlib>
#include <spawn.h>
#include <stdexcept>
#include <sys/wait.h>
#include <unistd.h>

namespace kurage::pipeline {

namespace fs = std::filesystem;

namespace {

// Runs a program with arguments (no shell); returns its exit status, or -1.
int runProgram(const std::vector<std::string>& argv) {
  std::vector<char*> args;
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  pid_t pid = 0;
  if (posix_spawnp(&pid, args[0], nullptr, nullptr, args.data(), environ) != 0) return -1;
  int status = 0;
  if (waitpid(pid, &status, 0) != pid) return -1;
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace

bool onPath(const std::string& program) {
  const char* path = std::getenv("PATH");
  if (!path) return false;
  std::string all(path);
  size_t start = 0;
  while (start <= all.size()) {
    const size_t end = std::min(all.find(':', start), all.size());
    const fs::path candidate = fs::path(all.substr(start, end - start)) / program;
    if (end > start && ::access(candidate.c_str(), X_OK) == 0) return true;
    start = end + 1;
  }
  return false;
}

VideoResult encodeVideo(const fs::path& framesFolder, int first, int count, double fps, const fs::path& movie) {
  char rate[32];
  std::snprintf(rate, sizeof rate, "%g", fps);
  const std::vector<std::string> command = {
      "ffmpeg", "-nostdin", "-y", "-loglevel", "error", "-framerate", rate, "-start_number", std::to_string(first),
      "-i", (framesFolder / "%04d.png").string(), "-frames:v", std::to_string(count), "-c:v", "libx264", "-pix_fmt",
      "yuv420p", "-vf", "pad=ceil(iw/2)*2:ceil(ih/2)*2", "-f", "mp4", temporaryPathFor(movie).string()};
  VideoResult result;
  for (const std::string& part : command) {
    const std::string shown = &part == &command.back() ? movie.string() : part;
    result.command += (result.command.empty() ? "" : " ") +
                      (shown.find_first_of("*()%") != std::string::npos ? "'" + shown + "'" : shown);
  }
  if (!onPath("ffmpeg")) return result;
  const int status = runProgram(command);
  if (status != 0) {
    std::error_code ignored;
    fs::remove(temporaryPathFor(movie), ignored);
    throw std::runtime_error("ffmpeg failed (exit status " + std::to_string(status) + ") encoding " + movie.string());
  }
  fs::rename(temporaryPathFor(movie), movie);
  result.encoded = true;
  return result;
}

void encodeVideoAndReport(const fs::path& framesFolder, int first, int count, double fps, const fs::path& movie) {
  const VideoResult video = encodeVideo(framesFolder, first, count, fps, movie);
  if (video.encoded)
    std::printf("video: %s\n", movie.string().c_str());
  else
    std::printf("ffmpeg is not on the PATH (Debian: apt-get install ffmpeg); the frames stay in %s; to make a video: %s\n",
                framesFolder.string().c_str(), video.command.c_str());
}

}  // namespace kurage::pipeline
