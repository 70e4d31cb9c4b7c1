// kurage farm SCENE -o OUT [...] [--submit] | kurage farm status OUT | kurage farm merge OUT
// (pipeline/farm/farm.h).
#include "pipeline/commands/cli.h"
#include "pipeline/interrupt.h"
#include "pipeline/farm/farm.h"
#include "pipeline/stages.h"
#include "pipeline/io/files.h"
#include "pipeline/io/json_file.h"
#include "pipeline/io/process.h"
#include "pipeline/report/run_report.h"
#include "pipeline/scene.h"

#include <algorithm>
#include <array>
#include <cstdio>
#include <map>
#include <sstream>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

namespace kurage::pipeline {

namespace fs = std::filesystem;

namespace {

const char* const kHelp =
    "usage: kurage farm SCENE -o OUT [--quality preview|final] [--frames A-B] [--frames-per-task K]\n"
    "                   [--max-tasks N] [--threads N] [--partition P] [--time-limit T]\n"
    "                   [--sbatch-arg ARG]... [--submit]\n"
    "       kurage farm status OUT\n"
    "       kurage farm merge OUT\n\n"
    "Hands a run to Slurm: writes OUT/farm/sim.sbatch (the simulation, one job), frames.sbatch (a\n"
    "job array: surface and render of a chunk of frames per task, after the simulation) and\n"
    "merge.sbatch (after the array: `kurage farm merge`, which assembles OUT/run.json from the tasks'\n"
    "records, encodes OUT/NAME.mp4 and writes OUT/report.html). The frames equal those of `kurage\n"
    "run`. OUT, the scene file and the kurage binary must be at the same absolute paths on every node\n"
    "(a shared file system).\n\n"
    "  --frames-per-task K  frames per array task (default 8)\n"
    "  --max-tasks N        at most N array tasks (larger chunks)\n"
    "  --partition P, --time-limit T   #SBATCH --partition / --time of every job\n"
    "  --sbatch-arg ARG     an extra #SBATCH line for every job (repeatable), e.g. --sbatch-arg=--mem=4G\n"
    "  --threads N          worker threads of every task (default: the cores Slurm gives it)\n"
    "  --submit             submit with sbatch --parsable: only the work still missing on disk (the\n"
    "                       simulation if a cache is missing, the chunks with a missing frame), then\n"
    "                       the merge; prints the job ids and keeps them in OUT/farm/jobs.json\n\n"
    "status: each job's state (squeue/scontrol; no accounting database needed) and the frames\n"
    "        missing on disk. merge: run by the last job; fails naming missing frames.\n";

struct Captured {
  int status = -1;
  std::string output;
};

// Runs a shell command, stdout and stderr together.
Captured capture(const std::string& command) {
  Captured c;
  FILE* pipe = popen((command + " 2>&1").c_str(), "r");
  if (!pipe) return c;
  std::array<char, 4096> buffer;
  size_t n;
  while ((n = fread(buffer.data(), 1, buffer.size(), pipe)) > 0) c.output.append(buffer.data(), n);
  const int status = pclose(pipe);
  c.status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return c;
}

std::string trim(std::string s) {
  while (!s.empty() && (s.back() == '\n' || s.back() == ' ')) s.pop_back();
  return s;
}

fs::path selfPath() {
  std::error_code ec;
  const fs::path p = fs::read_symlink("/proc/self/exe", ec);
  if (ec) throw std::runtime_error("cannot find the kurage binary (/proc/self/exe): " + ec.message());
  return p;
}

// sbatch --parsable [extra] SCRIPT -> the job id. Throws with sbatch's own message.
std::string sbatch(const std::string& extra, const fs::path& script) {
  const Captured c = capture("sbatch --parsable " + extra + " " + shellWord(script.string()));
  if (c.status != 0)
    throw std::runtime_error("sbatch " + script.filename().string() + " failed (exit " + std::to_string(c.status) +
                             "): " + trim(c.output) + "\nthe scripts are in " + script.parent_path().string());
  std::string id = trim(c.output);
  if (const size_t semicolon = id.find(';'); semicolon != std::string::npos) id.resize(semicolon);  // id;cluster
  return id;
}

FarmPlan loadPlan(const fs::path& out) {
  const fs::path file = out / "farm/plan.json";
  if (!fs::exists(file)) throw UsageError(file.string() + ": missing; OUT must be a folder made by `kurage farm`");
  return planFromJson(readJson(file), file.string());
}

// The scene a plan was made from, at the plan's quality (for the stage table's checks).
Scene planScene(const FarmPlan& plan) {
  Scene scene = loadScene(plan.sceneFile.string());
  applyQuality(scene, plan.quality == "final" ? Quality::Final : Quality::Preview);
  return scene;
}

int farmPlanAndSubmit(ArgParser& args) {
  const Quality quality = parseQuality(args);
  const std::optional<int> perTask = args.intOption({"--frames-per-task"}, 1, 1000000);
  const std::optional<int> maxTasks = args.intOption({"--max-tasks"}, 1, 1000000);
  const std::optional<std::string> partition = args.option({"--partition"});
  const std::optional<std::string> timeLimit = args.option({"--time-limit"});
  const std::vector<std::string> sbatchArgs = args.options({"--sbatch-arg"});
  const bool submit = args.flag({"--submit"});
  const StageCommandOptions options = parseStageOptions(args, true);
  const std::vector<std::string> positional = args.positionals();
  if (positional.size() != 1) args.fail("expected one SCENE");
  if (submit && !options.stage.outDir.is_absolute())
    args.fail("-o " + options.stage.outDir.string() +
              ": with --submit OUT must be an absolute path on a file system every node sees");

  Scene scene = loadScene(positional[0]);
  applyQuality(scene, quality);
  const auto [first, last] = frameRange(scene, options.stage);
  FarmPlan plan;
  plan.kurage = selfPath();
  plan.sceneFile = fs::absolute(positional[0]).lexically_normal();
  plan.outDir = fs::absolute(options.stage.outDir).lexically_normal();
  plan.sceneName = scene.name;
  plan.quality = quality == Quality::Preview ? "preview" : "final";
  plan.first = first;
  plan.last = last;
  plan.chunks = frameChunks(first, last, perTask.value_or(8), maxTasks.value_or(0));
  plan.threads = options.threads;
  plan.partition = partition.value_or("");
  plan.timeLimit = timeLimit.value_or("");
  plan.sbatchArgs = sbatchArgs;
  plan.fps = scene.output.fps;
  if (const std::string problem = farmPlanProblem(plan); !problem.empty()) args.fail(problem);

  const fs::path farm = plan.outDir / "farm";
  outputFolder(plan.outDir, "farm/logs");
  writeTextAtomic(farm / "plan.json", planToJson(plan).dump(2) + "\n");
  for (const auto& [name, text] : {std::pair{"sim.sbatch", simScript(plan)}, std::pair{"frames.sbatch", framesScript(plan)},
                                   std::pair{"merge.sbatch", mergeScript(plan)}}) {
    writeTextAtomic(farm / name, text);
    ::chmod((farm / name).c_str(), 0755);
  }
  std::printf("farm: %s (sim.sbatch, frames.sbatch: %zu tasks of up to %d frames, merge.sbatch)\n",
              farm.string().c_str(), plan.chunks.size(), plan.chunks.front().last - plan.chunks.front().first + 1);
  if (!submit) return 0;

  const FarmProgress progress = farmProgress(plan, scene);
  const std::string dependency = " --kill-on-invalid-dep=yes --dependency=afterok:";
  // jobs.json is rewritten after each submission: if a later sbatch fails, it still names the
  // jobs already queued (and no stale file from an earlier submission is left).
  nlohmann::json jobs = nlohmann::json::object();
  fs::remove(farm / "jobs.json");
  std::string after;
  if (progress.simNeeded()) {
    const std::string id = sbatch("", farm / "sim.sbatch");
    jobs["sim"] = id;
    writeTextAtomic(farm / "jobs.json", jobs.dump(2) + "\n");
    after = id;
    std::printf("sim: job %s\n", id.c_str());
  }
  if (!progress.chunksToRun.empty()) {
    std::string array;
    for (int c : progress.chunksToRun) {
      array += array.empty() ? "" : ",";
      array += std::to_string(c);
    }
    const std::string id = sbatch("--array=" + array + (after.empty() ? "" : dependency + after), farm / "frames.sbatch");
    jobs["frames"] = id;
    jobs["frame_tasks"] = progress.chunksToRun;
    writeTextAtomic(farm / "jobs.json", jobs.dump(2) + "\n");
    after = id;
    std::printf("frames: job %s (tasks %s)\n", id.c_str(), array.c_str());
  }
  const std::string id = sbatch(after.empty() ? "" : dependency + after, farm / "merge.sbatch");
  jobs["merge"] = id;
  std::printf("merge: job %s\n", id.c_str());
  writeTextAtomic(farm / "jobs.json", jobs.dump(2) + "\n");
  return 0;
}

// JobState of every record `scontrol show job -o ID` prints (one per array task), by task.
std::map<std::string, std::string> jobStates(const std::string& id) {
  std::map<std::string, std::string> states;
  const Captured c = capture("scontrol show job -o " + shellWord(id));
  if (c.status != 0) return states;
  std::istringstream lines(c.output);
  for (std::string line; std::getline(lines, line);) {
    auto field = [&](const std::string& key) {
      const size_t at = line.find(key + "=");
      if (at == std::string::npos) return std::string();
      const size_t start = at + key.size() + 1;
      return line.substr(start, line.find(' ', start) - start);
    };
    const std::string state = field("JobState");
    if (state.empty()) continue;
    const std::string task = field("ArrayTaskId");
    states[task.empty() ? "-" : task] = state;
  }
  return states;
}

int farmStatus(ArgParser& args) {
  const std::vector<std::string> positional = args.positionals();
  if (positional.size() != 1) args.fail("expected one OUT folder");
  const FarmPlan plan = loadPlan(positional[0]);
  const fs::path jobsFile = plan.outDir / "farm/jobs.json";
  if (fs::exists(jobsFile)) {
    const nlohmann::json jobs = readJson(jobsFile);
    for (const char* stage : {"sim", "frames", "merge"}) {
      if (!jobs.contains(stage)) {
        std::printf("%-6s not submitted (nothing to do)\n", stage);
        continue;
      }
      const std::string id = jobs[stage].get<std::string>();
      const auto states = jobStates(id);
      if (states.empty()) {
        std::printf("%-6s job %s: no longer known to Slurm\n", stage, id.c_str());
        continue;
      }
      std::map<std::string, int> count;
      for (const auto& [task, state] : states) ++count[state];
      std::string summary;
      for (const auto& [state, n] : count) {
        summary += summary.empty() ? "" : ", ";
        summary += std::to_string(n) + " " + state;
      }
      std::printf("%-6s job %s: %s\n", stage, id.c_str(), summary.c_str());
    }
  } else {
    std::printf("not submitted (no %s)\n", jobsFile.string().c_str());
  }
  const FarmProgress p = farmProgress(plan, planScene(plan));
  const int frames = plan.last - plan.first + 1;
  std::printf("on disk: caches %d of %d, surfaces %d of %d, frames %d of %d\n",
              frames - int(p.missingCaches.size()), frames, frames - int(p.missingSurfaces.size()), frames,
              frames - int(p.missingFrames.size()), frames);
  if (!p.missingFrames.empty()) {
    std::string tasks;
    for (int c : p.chunksToRun) {
      tasks += tasks.empty() ? "" : ",";
      tasks += std::to_string(c);
    }
    std::printf("missing frames: %s (tasks %s)\n", frameList(p.missingFrames).c_str(), tasks.c_str());
  } else {
    std::printf("missing frames: none\n");
  }
  return 0;
}

int farmMerge(ArgParser& args) {
  const std::vector<std::string> positional = args.positionals();
  if (positional.size() != 1) args.fail("expected one OUT folder");
  const FarmPlan plan = loadPlan(positional[0]);
  const Scene scene = planScene(plan);
  const FarmProgress p = farmProgress(plan, scene);
  if (!p.missingFrames.empty())
    throw std::runtime_error(plan.outDir.string() + ": frames " + frameList(p.missingFrames) +
                             " are missing; `kurage farm status` says which tasks failed");
  // run.json: the simulation's record, with the surface and render tasks' records merged.
  const fs::path records = plan.outDir / "records";
  const fs::path simRecord = records / "sim.json";
  nlohmann::json run = fs::exists(simRecord) ? readJson(simRecord)
                       : fs::exists(plan.outDir / "run.json") ? readJson(plan.outDir / "run.json")
                                                              : nlohmann::json::object();
  for (const StageSpec& spec : stageTable()) {
    if (spec.sequential || !spec.perFrame) continue;  // the per-frame stages the frame tasks ran
    const std::string stage = spec.name;
    std::vector<fs::path> files;
    for (const auto& entry : fs::directory_iterator(records)) {
      const std::string name = entry.path().filename().string();
      if (name.rfind(stage + "-", 0) == 0 && entry.path().extension() == ".json") files.push_back(entry.path());
    }
    std::sort(files.begin(), files.end());
    std::vector<std::pair<std::string, nlohmann::json>> tasks;
    for (const fs::path& file : files) tasks.emplace_back(file.filename().string(), readJson(file));
    run["stages"][stage] = mergeStageRecords(stage, tasks, plan.last - plan.first + 1);
  }
  run["farm"] = planToJson(plan);
  if (fs::exists(plan.outDir / "farm/jobs.json"))
    run["farm"]["jobs"] = readJson(plan.outDir / "farm/jobs.json");
  writeTextAtomic(plan.outDir / "run.json", run.dump(2) + "\n");
  std::printf("run: %s\n", (plan.outDir / "run.json").string().c_str());
  installInterruptHandlers();  // a signal during the encode ends ffmpeg: exit 128 + the signal
  encodeSceneVideo(scene, plan.outDir, plan.first, plan.last);
  writeRunReport(plan.outDir);
  std::printf("report: %s\n", (plan.outDir / "report.html").string().c_str());
  return 0;
}

}  // namespace

int commandFarm(std::vector<std::string> rawArgs) {
  if (!rawArgs.empty() && (rawArgs[0] == "status" || rawArgs[0] == "merge")) {
    const std::string sub = rawArgs[0];
    ArgParser args("farm " + sub, std::vector<std::string>(rawArgs.begin() + 1, rawArgs.end()));
    if (args.flag({"-h", "--help"})) {
      std::fputs(kHelp, stdout);
      return 0;
    }
    return sub == "status" ? farmStatus(args) : farmMerge(args);
  }
  ArgParser args("farm", std::move(rawArgs));
  if (args.flag({"-h", "--help"})) {
    std::fputs(kHelp, stdout);
    return 0;
  }
  return farmPlanAndSubmit(args);
}

}  // namespace kurage::pipeline
