// OUT/run.json: what a run did, for the user and for the next run. It holds the scene file, the
// versions of kurage and its libraries, the parameters in effect (the scene as parsed, every
// default filled in), quantities derived from them (particle mass, support radius, the stability
// bound at rest), and per stage its frames, seconds and figures: for the simulation its steps,
// active step bounds, the time of each step stage, the pressure solver's iterations and errors
// and the bodies' springs, collisions and shell summaries (pipeline/analysis/body_track.h).
// A farm task writes OUT/records/TASK.json instead; `kurage farm merge` assembles run.json.
#pragma once

#include "pipeline/analysis/body_track.h"
#include "pipeline/scene.h"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>

namespace kurage::sim {
class Simulation;
}

namespace kurage::pipeline {

// OUT/run.json, read if it exists (so single-stage commands add to it) and rewritten atomically.
class RunRecord {
public:
  // OUT/run.json, or OUT/records/TASK.json for a farm task (`task` not empty).
  RunRecord(const std::filesystem::path& outDir, const Scene& scene, const std::string& sceneFile,
            const std::string& task = "");
  nlohmann::json& data() { return data_; }
  void setStage(const std::string& name, nlohmann::json stage);
  void save() const;

private:
  std::filesystem::path path_;
  nlohmann::json data_;
};

// Versions of kurage and the libraries it uses.
nlohmann::json versionInfo();

// What the sim stage did besides what the simulation knows of itself.
struct SimStageRun {
  double seconds = 0.0;
  int first = 0, last = 0;           // the frames written
  int resumedAfter = -1;             // the checkpoint's frame a --resume continued after; -1: none
  std::filesystem::path checkpoint;  // OUT/checkpoint.bin
  int checkpointFrame = -1;          // the frame the newest checkpoint holds
  int checkpointEvery = 0;           // frames between checkpoints (0: only the last and on a signal)
};

// The sim stage's entries: stages.sim (steps, bounds, step phases, the solver), derived,
// stages.sim.bodies with each shell's summary and stages.sim.pours with the emitters' account,
// both from `track`. Where body particles were left out of the pressure solves, or a solve or the
// bodies' collision loop stopped at its cap, it warns on stderr and lists the warning in
// stages.sim.warnings ({message, key}: the entry with the figures). The caller saves.
void recordSimStage(RunRecord& record, const Scene& scene, const sim::Simulation& simulation, const BodyTrack& track,
                    const SimStageRun& run);

}  // namespace kurage::pipeline
