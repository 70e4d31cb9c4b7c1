// Checkpoints of the simulation stage: OUT/checkpoint.bin, the full state after a frame (or after
// the step in which a signal stopped the next frame), from which `kurage sim|run --resume`
// continues bit for bit (docs/design/reliability.md). The simulation writes one every
// --checkpoint-every frames, after the last frame, and when SIGINT or SIGTERM stops it; each
// replaces the one before atomically (pipeline/io/files.h).
//
// Layout: the line "KURAGE-CHECKPOINT 1\n"; the kurage:checksum field (pipeline/io/stamp.h,
// FNV-1a 64 of the whole file, checked before anything else is read); a u32 length and a JSON
// header {"stage": "checkpoint", "scene_hash", "frame", "time", "kurage", "sim_state_bytes",
// "stage_state_bytes"}; the simulation's state (sim/state.h) and the sim stage's own (the
// per-frame records of bodies.csv and sim_frames.csv). A checkpoint is read back only by the kurage version
// that wrote it, for the scene (the simulation's stage hash) it was made from.
#pragma once

#include <filesystem>
#include <string>

namespace kurage::pipeline {

struct Checkpoint {
  int frame = -1;          // the last frame done
  double time = 0.0;       // the state's simulated time, s: the frame's, or later when a signal
                           // stopped the next frame between two steps
  std::string simState;    // sim::Simulation::saveState
  std::string stageState;  // the sim stage's records
};

// OUT/checkpoint.bin.
std::filesystem::path checkpointFile(const std::filesystem::path& outDir);

// Writes atomically. Throws IoError naming the path.
void writeCheckpoint(const std::filesystem::path& path, const Checkpoint& checkpoint, const std::string& simHash);

// Reads and checks a checkpoint: its checksum, then that it was made by this kurage for the scene
// whose simulation hash is `simHash`. Throws IoError naming the path for a missing, damaged or
// foreign file.
Checkpoint readCheckpoint(const std::filesystem::path& path, const std::string& simHash);

}  // namespace kurage::pipeline
