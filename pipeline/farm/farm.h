// Frames on a cluster: a kurage run handed to Slurm as job scripts (sbatch), with the same
// results as `kurage run` (the tasks run the same stage commands on disjoint frame ranges).
//
//   OUT/farm/sim.sbatch     one job: `kurage sim` over the frames (a simulation is sequential in time)
//   OUT/farm/frames.sbatch  a job array over frame chunks: `kurage surface` then `kurage render`
//                           for the task's chunk, after the simulation (afterok)
//   OUT/farm/merge.sbatch   one job after the array (afterok): `kurage farm merge OUT` merges the
//                           tasks' records (OUT/records/*.json) into OUT/run.json and encodes the video
//   OUT/farm/plan.json      the plan: scene, binary, quality, frames and chunks
//   OUT/farm/jobs.json      the job ids of the last submission (kurage farm --submit)
// Dependencies use --kill-on-invalid-dep=yes: when a job fails, the jobs after it are cancelled
// instead of pending forever. Each task writes its own record and takes no lock on OUT, so tasks
// never edit one file together. OUT must be on a file system every node sees (shared), at the
// same absolute path, as must the scene file and the kurage binary.
#pragma once

#include "pipeline/scene.h"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace kurage::pipeline {

struct FarmChunk {
  int first = 0, last = 0;  // frames, inclusive
};

struct FarmPlan {
  std::filesystem::path kurage;     // absolute path of the kurage binary the jobs run
  std::filesystem::path sceneFile;  // absolute
  std::filesystem::path outDir;     // absolute
  std::string sceneName;
  std::string quality = "final";
  int first = 0, last = 0;
  std::vector<FarmChunk> chunks;
  int threads = 0;  // --threads for every task (0: all the cores Slurm gives it)
  std::string partition, timeLimit;
  std::vector<std::string> sbatchArgs;  // extra #SBATCH lines, e.g. "--mem=4G"
  double fps = 24.0;
};

// Frames [first, last] cut into chunks of `framesPerTask` (>= 1), or into at most `maxTasks`
// chunks of equal size (but the last) when that is fewer.
std::vector<FarmChunk> frameChunks(int first, int last, int framesPerTask, int maxTasks);

// Why the plan's values cannot go into job scripts, naming the option ("--partition: ..."), or ""
// when they can. Every value that reaches a script is either a shell word (shellWord, io/process.h), a quoted
// #SBATCH value, or refused here: control characters anywhere (a newline would end a comment or
// an #SBATCH line and start a command), a partition other than letters, digits and _ . , -, a
// time limit other than letters, digits, ':' and '-'.
std::string farmPlanProblem(const FarmPlan& plan);

// The job scripts (bash with #SBATCH lines). Throw std::invalid_argument when farmPlanProblem
// finds a problem.
std::string simScript(const FarmPlan& plan);
std::string framesScript(const FarmPlan& plan);
std::string mergeScript(const FarmPlan& plan);

nlohmann::json planToJson(const FarmPlan& plan);
FarmPlan planFromJson(const nlohmann::json& json, const std::string& file);

// What is on disk for the plan's frames: which caches and PNG frames are missing, and so which
// chunks still have work (indices into plan.chunks).
struct FarmProgress {
  std::vector<int> missingCaches, missingSurfaces, missingFrames;
  std::vector<int> chunksToRun;
  bool simNeeded() const { return !missingCaches.empty(); }
};
// What is done on disk, by the stage table's upToDate (pipeline/stages.h) for `scene`, the scene
// of the plan at its quality.
FarmProgress farmProgress(const FarmPlan& plan, const Scene& scene);


// "3-5, 9" style list of frame numbers.
std::string frameList(const std::vector<int>& frames);

// One per-frame stage's entry of the merged OUT/run.json, from the frame tasks' records
// (OUT/records/STAGE-FIRST-LAST.json: each record's file name and content, in the order to list
// them): `seconds` the sum of the tasks' stage seconds, `frames` the plan's frame count, `tasks`
// each record's name and seconds, and `per_frame` every task's entries ({"frame": [...],
// "seconds": [...]}, docs/guide/outputs.md) joined and sorted by frame (stably: a frame two
// records hold is listed twice, in their order). A record without the stage counts 0 s and no frame.
nlohmann::json mergeStageRecords(const std::string& stage,
                                 const std::vector<std::pair<std::string, nlohmann::json>>& records, int frames);


}  // namespace kurage::pipeline
