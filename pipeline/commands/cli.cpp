#include "pipeline/commands/cli.h"

#include <cstdio>
#include <unistd.h>

namespace kurage::pipeline {

namespace {
bool matches(const std::string& arg, std::initializer_list<const char*> names) {
  for (const char* n : names)
    if (arg == n) return true;
  return false;
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
  size_t used = 0;
  int value = 0;
  try {
    value = std::stoi(*text, &used);
  } catch (...) {
    used = 0;
  }
  if (used != text->size() || value < min || value > max)
    fail(std::string(*names.begin()) + ": expected an integer in [" + std::to_string(min) + ", " +
         std::to_string(max) + "], got " + *text);
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
  if (used != text->size()) fail(std::string(*names.begin()) + ": expected a number, got " + *text);
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
    int first = 0, last = 0;
    char tail = 0;
    if (std::sscanf(frames->c_str(), "%d-%d%c", &first, &last, &tail) == 2) {
      o.stage.firstFrame = first;
      o.stage.lastFrame = last;
    } else if (std::sscanf(frames->c_str(), "%d%c", &first, &tail) == 1) {
      o.stage.firstFrame = o.stage.lastFrame = first;
    } else {
      args.fail("--frames: expected A-B or A, got " + *frames);
    }
    if (o.stage.firstFrame < 0 || o.stage.lastFrame < o.stage.firstFrame) args.fail("--frames: bad range " + *frames);
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
