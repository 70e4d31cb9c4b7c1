#include "pipeline/commands/cli.h"

#include "pipeline/interrupt.h"
#include "pipeline/io/files.h"
#include "pipeline/io/json_file.h"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <unistd.h>

namespace kurage::pipeline {

namespace {
bool matches(const std::string& arg, std::initializer_list<const char*> names) {
  for (const char* n : names)
    if (arg == n) return true;
  return false;
}

// The whole of `text` as a decimal integer in [min, max]; nullopt for anything else (no sign
// other than '-', no spaces, no wrap-around: 4294967298 is out of range, not 2).
std::optional<int> parseInteger(std::string_view text, int min, int max) {
  long long value = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (text.empty() || error != std::errc() || end != text.data() + text.size() || value < min || value > max)
    return std::nullopt;
  return int(value);
}
}  // namespace

void ArgParser::fail(const std::string& message) const { throw UsageError(command_ + ": " + message); }

bool ArgParser::flag(std::initializer_list<const char*> names) {
  bool found = false;
  for (size_t i = 0; i < args_.size();) {
    if (matches(args_[i], names)) {
      found = true;
      args_.erase(args_.begin() + long(i));
    } else {
      ++i;
    }
  }
  return found;
}

std::optional<std::string> ArgParser::option(std::initializer_list<const char*> names) {
  std::optional<std::string> value;
  for (size_t i = 0; i < args_.size();) {
    if (matches(args_[i], names)) {
      if (i + 1 >= args_.size()) fail(args_[i] + " needs a value");
      value = args_[i + 1];
      args_.erase(args_.begin() + long(i), args_.begin() + long(i) + 2);
    } else {
      ++i;
    }
  }
  return value;
}

std::vector<std::string> ArgParser::options(std::initializer_list<const char*> names) {
  std::vector<std::string> values;
  for (size_t i = 0; i < args_.size();) {
    if (matches(args_[i], names)) {
      if (i + 1 >= args_.size()) fail(args_[i] + " needs a value");
      values.push_back(args_[i + 1]);
      args_.erase(args_.begin() + long(i), args_.begin() + long(i) + 2);
    } else {
      ++i;
    }
  }
  return values;
}

std::optional<int> ArgParser::intOption(std::initializer_list<const char*> names, int min, int max) {
  const std::optional<std::string> text = option(names);
  if (!text) return std::nullopt;
  const std::optional<int> value = parseInteger(*text, min, max);
  if (!value)
    fail(std::string(*(names.end() - 1)) + ": expected an integer in [" + std::to_string(min) + ", " +
         std::to_string(max) + "], got " + textExcerpt(*text));
  return value;
}

std::optional<double> ArgParser::doubleOption(std::initializer_list<const char*> names) {
  const std::optional<std::string> text = option(names);
  if (!text) return std::nullopt;
  size_t used = 0;
  double value = 0;
  try {
    value = std::stod(*text, &used);
  } catch (...) {
    used = 0;
  }
  if (text->empty() || used != text->size() || !std::isfinite(value))
    fail(std::string(*(names.end() - 1)) + ": expected a finite number, got " + textExcerpt(*text));
  return value;
}

std::vector<std::string> ArgParser::positionals() {
  for (const std::string& a : args_)
    if (a.size() > 1 && a[0] == '-') fail("unknown option " + a);
  return args_;
}

const char* const kStageOptionsHelp =
    "  -o, --output OUT   output folder (created if missing)\n"
    "  --frames A-B       only frames A to B (0-based, inclusive; or a single frame A);\n"
    "                     the simulation still starts at t = 0\n"
    "  --threads N        worker threads (default: all cores)\n"
    "  --progress         show progress on stderr even when it is not a terminal\n"
    "  --task NAME        (farm jobs) record into OUT/records/NAME.json, not OUT/run.json\n"
    "  --force            run a scene above the size limits (docs/design/reliability.md)\n"
    "  --resume           (sim, run) continue the simulation from OUT/checkpoint.bin, bit for bit\n"
    "  --checkpoint-every N  (sim, run) write OUT/checkpoint.bin every N frames (default 10; 0:\n"
    "                     only after the last frame and on SIGINT/SIGTERM)\n"
    "  -h, --help         this help\n";

StageCommandOptions parseStageOptions(ArgParser& args, bool requireOutput) {
  StageCommandOptions o;
  o.stage.progress = args.flag({"--progress"}) || isatty(STDERR_FILENO);
  o.stage.force = args.flag({"--force"});
  o.stage.resume = args.flag({"--resume"});
  if (auto every = args.intOption({"--checkpoint-every"}, 0, 1000000)) o.stage.checkpointEvery = *every;
  if (auto out = args.option({"-o", "--output"})) o.stage.outDir = *out;
  else if (requireOutput) args.fail("missing -o OUT");
  if (auto t = args.intOption({"--threads"}, 1, 1024)) o.threads = *t;
  if (auto task = args.option({"--task"})) {
    if (task->empty() || task->find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_.-") !=
                             std::string::npos || task->front() == '.')
      args.fail("--task: a plain name of letters, digits, '_', '.' and '-', got " + *task);
    o.stage.task = *task;
  }
  if (auto frames = args.option({"--frames"})) {
    // A or A-B, each a frame number in [0, kMaxFramesHard).
    const size_t dash = frames->find('-');
    const std::optional<int> first = parseInteger(std::string_view(*frames).substr(0, dash), 0, int(kMaxFramesHard) - 1);
    const std::optional<int> last =
        dash == std::string::npos ? first : parseInteger(std::string_view(*frames).substr(dash + 1), 0, int(kMaxFramesHard) - 1);
    if (!first || !last)
      args.fail("--frames: expected A-B or A, frame numbers from 0 to " + std::to_string(int(kMaxFramesHard) - 1) +
                ", got " + textExcerpt(*frames));
    if (*last < *first) args.fail("--frames: bad range " + *frames + " (B before A)");
    o.stage.firstFrame = *first;
    o.stage.lastFrame = *last;
  }
  return o;
}

std::pair<int, int> checkedFrameRange(const ArgParser& args, const Scene& scene, const StageOptions& options) {
  try {
    return frameRange(scene, options);
  } catch (const std::invalid_argument& e) {
    args.fail(e.what());
  }
}

ClaimedOutput::ClaimedOutput(const std::filesystem::path& outDir, const std::string& command, const std::string& task) {
  if (task.empty()) {
    lock_.emplace(outDir, command);
    if (const size_t stale = removeStaleTemporaries(outDir))
      std::printf("%s: removed %zu temporary files left by a run that was killed\n",
                  command.substr(0, command.find(' ')).c_str(), stale);
  }
  installInterruptHandlers();
}

const char* const kQualityHelp =
    "  --quality Q        final (default: the scene as written) or preview (the scene's preview_quality:\n"
    "                     by default half the resolution, a quarter of the samples, depth <= 6,\n"
    "                     surface voxels twice as large)\n";

Quality parseQuality(ArgParser& args) {
  const std::optional<std::string> q = args.option({"--quality"});
  if (!q || *q == "final") return Quality::Final;
  if (*q == "preview") return Quality::Preview;
  args.fail("--quality: expected preview or final, got " + *q);
}

}  // namespace kurage::pipeline
