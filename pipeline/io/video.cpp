#include "pipeline/io/video.h"

#include "pipeline/io/files.h"
#include "pipeline/io/process.h"

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <csignal>
#include <sys/prctl.h>
#include <stdexcept>
#include <sys/wait.h>
#include <unistd.h>

namespace kurage::pipeline {

namespace fs = std::filesystem;

namespace {

std::string trimmed(std::string text) {
  while (!text.empty() && (text.back() == '\n' || text.back() == '\r' || text.back() == ' ')) text.pop_back();
  return text;
}

// What ffprobe reads of a movie: its first video stream's frame count and the comment tag;
// nullopt when ffprobe is missing or cannot read the file.
struct Probe {
  std::string frames, comment;
};
std::optional<Probe> probe(const fs::path& movie) {
  if (!onPath("ffprobe")) return std::nullopt;
  std::string out;
  if (runProgram({"ffprobe", "-v", "error", "-select_streams", "v:0", "-show_entries",
                  "stream=nb_frames:format_tags=comment", "-of", "default=noprint_wrappers=1", movie.string()},
                 &out) != 0)
    return std::nullopt;
  Probe p;
  size_t start = 0;
  while (start < out.size()) {
    const size_t end = std::min(out.find('\n', start), out.size());
    const std::string line = out.substr(start, end - start);
    if (line.rfind("nb_frames=", 0) == 0) p.frames = line.substr(10);
    if (line.rfind("TAG:comment=", 0) == 0) p.comment = line.substr(12);
    start = end + 1;
  }
  return p;
}

constexpr std::string_view kStampPrefix = "kurage:stamp ";

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

VideoResult encodeVideo(const fs::path& framesFolder, int first, int count, double fps, const fs::path& movie,
                        const std::string& stamp, bool force, const StopRequested& stop) {
  char rate[32];
  std::snprintf(rate, sizeof rate, "%g", fps);
  std::vector<std::string> command = {
      "ffmpeg", "-nostdin", "-y", "-loglevel", "error", "-framerate", rate, "-start_number", std::to_string(first),
      "-i", (framesFolder / "%04d.png").string(), "-frames:v", std::to_string(count), "-c:v", "libx264", "-pix_fmt",
      "yuv420p", "-vf", "pad=ceil(iw/2)*2:ceil(ih/2)*2", "-f", "mp4", movie.string()};
  if (!stamp.empty()) command.insert(command.end() - 1, {"-metadata", "comment=" + std::string(kStampPrefix) + stamp});
  VideoResult result;
  for (const std::string& part : command) {
    const std::string& shown = part;
    result.command += (result.command.empty() ? "" : " ") +
                      (shown.find_first_of("*()%") != std::string::npos ? "'" + shown + "'" : shown);
  }
  if (!stamp.empty() && !force && fs::exists(movie)) {
    const std::optional<Probe> found = probe(movie);
    if (found && found->frames == std::to_string(count) && found->comment == std::string(kStampPrefix) + stamp) {
      result.upToDate = true;
      return result;
    }
  }
  if (!onPath("ffmpeg")) return result;
  // ffmpeg writes the temporary (unique, created exclusively); the movie is accepted only when
  // ffmpeg exits 0 and prints no error (it exits 0 after "Error writing trailer" on a full disk)
  // and ffprobe reads back the expected number of frames.
  TempFile temporary(movie);
  command.back() = temporary.path().string();
  std::string log;
  const int status = runProgram(command, &log, stop);
  if (status == kProgramStopped) throw IoError(movie.string() + ": stopped before ffmpeg finished; no movie written");
  if (status != 0 || !trimmed(log).empty())
    throw IoError(movie.string() + ": ffmpeg failed (exit status " + std::to_string(status) + ")" +
                  (trimmed(log).empty() ? "" : ": " + trimmed(log)));
  if (onPath("ffprobe")) {
    std::string probed;
    const int probeStatus = runProgram({"ffprobe", "-v", "error", "-select_streams", "v:0", "-show_entries",
                                        "stream=nb_frames", "-of", "default=noprint_wrappers=1:nokey=1",
                                        temporary.path().string()},
                                       &probed);
    if (probeStatus != 0 || trimmed(probed) != std::to_string(count))
      throw IoError(movie.string() + ": the encoded movie does not check out: ffprobe " +
                    (probeStatus != 0 ? "failed (exit status " + std::to_string(probeStatus) + ")" : "counts") + " " +
                    trimmed(probed) + (probeStatus != 0 ? "" : " frames, expected " + std::to_string(count)));
  } else if (std::filesystem::file_size(temporary.path()) == 0) {
    throw IoError(movie.string() + ": ffmpeg wrote an empty file");
  }
  temporary.commit();
  result.encoded = true;
  return result;
}

void encodeVideoAndReport(const fs::path& framesFolder, int first, int count, double fps, const fs::path& movie,
                          const std::string& stamp, bool force, const StopRequested& stop) {
  const VideoResult video = encodeVideo(framesFolder, first, count, fps, movie, stamp, force, stop);
  if (video.upToDate)
    std::printf("video: %s (up to date: made from the same frames and settings)\n", movie.string().c_str());
  else if (video.encoded)
    std::printf("video: %s\n", movie.string().c_str());
  else
    std::printf("ffmpeg is not on the PATH (Debian: apt-get install ffmpeg); the frames stay in %s; to make a video: %s\n",
                framesFolder.string().c_str(), video.command.c_str());
}

}  // namespace kurage::pipeline
