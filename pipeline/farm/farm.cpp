#include "pipeline/farm/farm.h"

#include "pipeline/io/files.h"
#include "pipeline/io/process.h"
#include "pipeline/param_visitor.h"
#include "pipeline/stages.h"

#include <algorithm>
#include <cctype>
#include <cstring>
#include <stdexcept>
#include <sstream>

namespace kurage::pipeline {

namespace fs = std::filesystem;

namespace {

bool hasControlCharacter(const std::string& s) {
  for (const char c : s)
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) return true;
  return false;
}

bool onlyCharacters(const std::string& s, const char* punctuation) {
  for (const char c : s)
    if (!std::isalnum(static_cast<unsigned char>(c)) && !std::strchr(punctuation, c)) return false;
  return true;
}

// Text for inside the double quotes of an #SBATCH value as sbatch reads it (get_argument in
// Slurm's sbatch/opt.c: quotes group, a backslash escapes the next character): \ and " escaped.
// In a file name pattern (--output) a literal % is written %%.
std::string sbatchQuoted(const std::string& s, bool filePattern) {
  std::string out;
  for (const char c : s) {
    if (c == '\\' || c == '"') out += '\\';
    out += c;
    if (filePattern && c == '%') out += '%';
  }
  return out;
}

// The scene's name in a job name: letters, digits, _ . - only (the rest as _).
std::string jobNamePart(const std::string& s) {
  std::string out = s.substr(0, 64);
  for (char& c : out)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_' && c != '.' && c != '-') c = '_';
  return out;
}

std::string header(const FarmPlan& plan, const std::string& stage, const std::string& log) {
  if (const std::string problem = farmPlanProblem(plan); !problem.empty()) throw std::invalid_argument(problem);
  std::ostringstream s;
  s << "#!/bin/bash\n"
    << "# kurage farm: " << stage << " of " << plan.sceneFile.string() << " into " << plan.outDir.string() << "\n"
    << "#SBATCH --job-name=kurage-" << jobNamePart(plan.sceneName) << "-" << stage << "\n"
    << "#SBATCH --output=\"" << sbatchQuoted((plan.outDir / "farm/logs").string() + "/", true) << log << "\"\n";
  if (!plan.partition.empty()) s << "#SBATCH --partition=" << plan.partition << "\n";
  if (!plan.timeLimit.empty()) s << "#SBATCH --time=" << plan.timeLimit << "\n";
  for (const std::string& a : plan.sbatchArgs) s << "#SBATCH " << a << "\n";
  s << "set -euo pipefail\n";
  return s.str();
}

std::string common(const FarmPlan& plan) {
  std::string s = " ";
  s += shellWord(plan.sceneFile.string());
  s += " -o ";
  s += shellWord(plan.outDir.string());
  s += " --quality ";
  s += plan.quality;
  if (plan.threads > 0) {
    s += " --threads ";
    s += std::to_string(plan.threads);
  }
  return s;
}

}  // namespace

std::string farmPlanProblem(const FarmPlan& plan) {
  const auto lineSafe = [](const std::string& s) { return !hasControlCharacter(s); };
  if (!lineSafe(plan.outDir.string())) return "-o: OUT must not contain control characters (a newline, a tab, ...)";
  if (plan.outDir.string().find("packjob") != std::string::npos)
    return "-o: OUT must not contain \"packjob\" (sbatch takes it for a job separator)";
  if (!lineSafe(plan.sceneFile.string())) return "SCENE: the scene's path must not contain control characters";
  if (!lineSafe(plan.kurage.string())) return "the kurage binary's path must not contain control characters";
  if (!onlyCharacters(plan.partition, "_.,-"))
    return "--partition: letters, digits and _ . , - only, got " + shellWord(plan.partition);
  if (!onlyCharacters(plan.timeLimit, ":-"))
    return "--time-limit: Slurm's time format (minutes, [D-]HH:MM:SS, UNLIMITED), got " + shellWord(plan.timeLimit);
  for (const std::string& a : plan.sbatchArgs)
    if (!lineSafe(a)) return "--sbatch-arg: one #SBATCH line without control characters, got " + shellWord(a);
  if (plan.quality != "final" && plan.quality != "preview") return "--quality: final or preview, got " + shellWord(plan.quality);
  return "";
}

std::vector<FarmChunk> frameChunks(int first, int last, int framesPerTask, int maxTasks) {
  const int frames = last - first + 1;
  int size = std::max(1, framesPerTask);
  if (maxTasks > 0 && (frames + size - 1) / size > maxTasks) size = (frames + maxTasks - 1) / maxTasks;
  std::vector<FarmChunk> chunks;
  for (int f = first; f <= last; f += size) chunks.push_back({f, std::min(last, f + size - 1)});
  return chunks;
}

std::string simScript(const FarmPlan& plan) {
  return header(plan, "sim", "sim-%j.out") + "exec " + shellWord(plan.kurage.string()) + " sim" + common(plan) +
         " --frames " + std::to_string(plan.first) + "-" + std::to_string(plan.last) + " --task sim --resume\n";
}

std::string framesScript(const FarmPlan& plan) {
  std::string s = header(plan, "frames", "frames-%A_%a.out");
  s += "# The array index picks a chunk; submitted as --array=I,J,... (the chunks with work left).\nchunks=(";
  for (size_t i = 0; i < plan.chunks.size(); ++i) {
    s += i ? " " : "";
    s += std::to_string(plan.chunks[i].first) + "-" + std::to_string(plan.chunks[i].last);
  }
  s += ")\nrange=${chunks[$SLURM_ARRAY_TASK_ID]}\n";
  const std::string kurage = shellWord(plan.kurage.string());
  // Every per-frame stage of the table, in order (surface, render); export is the merge's.
  for (const StageSpec& stage : stageTable()) {
    if (stage.sequential || !stage.perFrame) continue;
    const std::string name = stage.name;
    s += kurage + " " + name + common(plan) + " --frames \"$range\"" + (name == "render" ? " --no-video" : "") +
         " --task \"" + name + "-$range\"\n";
  }
  return s;
}

std::string mergeScript(const FarmPlan& plan) {
  return header(plan, "merge", "merge-%j.out") + "exec " + shellWord(plan.kurage.string()) + " farm merge " +
         shellWord(plan.outDir.string()) + "\n";
}

nlohmann::json planToJson(const FarmPlan& plan) {
  nlohmann::json chunks = nlohmann::json::array();
  for (const FarmChunk& c : plan.chunks) chunks.push_back({c.first, c.last});
  return {{"kurage", plan.kurage.string()},   {"scene_file", plan.sceneFile.string()},
          {"out", plan.outDir.string()},      {"scene_name", plan.sceneName},
          {"quality", plan.quality},          {"frames", {plan.first, plan.last}},
          {"chunks", chunks},                 {"threads", plan.threads},
          {"partition", plan.partition},      {"time_limit", plan.timeLimit},
          {"sbatch_args", plan.sbatchArgs},   {"fps", plan.fps}};
}

FarmPlan planFromJson(const nlohmann::json& j, const std::string& file) {
  try {
    FarmPlan p;
    p.kurage = j.at("kurage").get<std::string>();
    p.sceneFile = j.at("scene_file").get<std::string>();
    p.outDir = j.at("out").get<std::string>();
    p.sceneName = j.at("scene_name").get<std::string>();
    p.quality = j.at("quality").get<std::string>();
    p.first = j.at("frames").at(0).get<int>();
    p.last = j.at("frames").at(1).get<int>();
    for (const auto& c : j.at("chunks")) p.chunks.push_back({c.at(0).get<int>(), c.at(1).get<int>()});
    p.threads = j.at("threads").get<int>();
    p.partition = j.at("partition").get<std::string>();
    p.timeLimit = j.at("time_limit").get<std::string>();
    p.sbatchArgs = j.at("sbatch_args").get<std::vector<std::string>>();
    p.fps = j.at("fps").get<double>();
    return p;
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error(file + ": not a kurage farm plan: " + e.what());
  }
}

FarmProgress farmProgress(const FarmPlan& plan, const Scene& scene) {
  FarmProgress p;
  // A frame is done for a stage when the stage table says its outputs are whole and from this
  // scene's inputs and settings (the same test the stages use to skip it).
  const StageContext context(scene, plan.outDir);
  const StageSpec& sim = findStage("sim");
  const StageSpec& surface = findStage("surface");
  const StageSpec& render = findStage("render");
  for (int f = plan.first; f <= plan.last; ++f) {
    if (!sim.upToDate(context, f)) p.missingCaches.push_back(f);
    if (!surface.upToDate(context, f)) p.missingSurfaces.push_back(f);
    if (!render.upToDate(context, f)) p.missingFrames.push_back(f);
  }
  for (size_t i = 0; i < plan.chunks.size(); ++i)
    for (int f : p.missingFrames)
      if (f >= plan.chunks[i].first && f <= plan.chunks[i].last) {
        p.chunksToRun.push_back(int(i));
        break;
      }
  return p;
}

std::string frameList(const std::vector<int>& frames) {
  std::string out;
  for (size_t i = 0; i < frames.size();) {
    size_t j = i;
    while (j + 1 < frames.size() && frames[j + 1] == frames[j] + 1) ++j;
    out += out.empty() ? "" : ", ";
    out += std::to_string(frames[i]);
    if (j > i) {
      out += '-';
      out += std::to_string(frames[j]);
    }
    i = j + 1;
  }
  return out;
}

nlohmann::json mergeStageRecords(const std::string& stage,
                                 const std::vector<std::pair<std::string, nlohmann::json>>& records, int frames) {
  double seconds = 0.0;
  nlohmann::json tasks = nlohmann::json::array();
  std::vector<std::pair<int, double>> made;  // (frame, seconds) of every task
  for (const auto& [name, record] : records) {
    const nlohmann::json entry = record.contains("stages") ? record["stages"].value(stage, nlohmann::json::object())
                                                           : nlohmann::json::object();
    const double taskSeconds = entry.value("seconds", 0.0);
    seconds += taskSeconds;
    tasks.push_back({{"record", name}, {"seconds", taskSeconds}});
    if (!entry.contains("per_frame")) continue;
    const nlohmann::json& frame = entry["per_frame"].at("frame");
    const nlohmann::json& frameSeconds = entry["per_frame"].at("seconds");
    if (frame.size() != frameSeconds.size())
      throw std::runtime_error(name + ": stages." + stage + ".per_frame: " + std::to_string(frame.size()) +
                               " frames but " + std::to_string(frameSeconds.size()) + " seconds");
    for (size_t k = 0; k < frame.size(); ++k) made.emplace_back(frame[k].get<int>(), frameSeconds[k].get<double>());
  }
  std::stable_sort(made.begin(), made.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  nlohmann::json perFrame = {{"frame", nlohmann::json::array()}, {"seconds", nlohmann::json::array()}};
  for (const auto& [frame, s] : made) {
    perFrame["frame"].push_back(frame);
    perFrame["seconds"].push_back(s);
  }
  return {{"seconds", seconds}, {"frames", frames}, {"tasks", std::move(tasks)}, {"per_frame", std::move(perFrame)}};
}

}  // namespace kurage::pipeline
