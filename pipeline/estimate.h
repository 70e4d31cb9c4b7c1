// How long `kurage run` takes, per stage: before it starts, from the scene's size and a machine's
// speed (`kurage check --estimate`), and while it runs, from its first measured frames.
//
// The model (seconds, on MachineSpeed::threads threads; `threads` others scale it by
// speed.threads / threads, as if the stages were perfectly parallel):
//   steps   = (frames - 1) * ceil(frame interval / step), the step the fixed one, or the
//             adaptive one at rest: min(time_step.max_step, the stability bound at rest)
//   sim     = particles * steps * simSecondsPerParticleStep
//   surface = frames * surfaceSecondsPerBlobVoxel * sum over surfaced particles of
//             (radius / voxel_size)^3 (x anisotropicSurfaceFactor for the anisotropic kernel)
//   render  = frames * width * height * samples * seconds per sample of the integrator
//   encode  = frames * width * height * encodeSecondsPerPixel (0 without a video)
// Limits: the particles are the scene's at t = 0 (an emitter's water is not counted); a flow that
// speeds up or collides shortens the adaptive step below the bound at rest and takes more steps;
// the render's cost per sample depends on the scene (depth, glass, the denoiser and adaptive
// sampling are not modelled). Measured against real runs in docs/notebook/rendering.md.
#pragma once

#include "pipeline/progress.h"

#include <array>
#include <string>
#include <vector>

namespace kurage::sim {
class Simulation;
}

namespace kurage::pipeline {

struct Scene;

// Seconds per unit of work on one machine at `threads` threads.
struct MachineSpeed {
  const char* machine;
  int threads;
  double simSecondsPerParticleStep;
  double surfaceSecondsPerBlobVoxel;
  double anisotropicSurfaceFactor;
  double whittedSecondsPerSample;
  double pathSecondsPerSample;
  double encodeSecondsPerPixel;
};

// The development machine (2-core AMD EPYC with AVX-512, 2 threads); where each figure comes
// from is in docs/guide/cli.md (`kurage check --estimate`).
inline constexpr MachineSpeed kDevelopmentMachine{
    "2-core AMD EPYC (AVX-512), 2 threads", 2,
    0.93e-6,   // the jellyfish, DFSPH with the corrected gradient on the lanes path (docs/guide/cli.md)
    1.21e-8,   // `kurage bench surface`: 100,949 particles, radius / voxel 4, 0.078 s
    2.25,      // the anisotropic level set against the isotropic one, 0.27 s / 0.12 s
    7.7e-7,    // whitted, jellyfish: 0.4 s per sample per pixel of a 960x540 frame
    9.9e-7,    // path, jellyfish: 8.2 s at 16 samples, 960x540
    3.2e-8,    // libx264 through ffmpeg: 361 frames of 480x270 in 1.5 s
};

// What a run has to do, from the scene (runSize) or a test.
struct RunSize {
  double particles = 0.0;       // simulated at t = 0 (fluid and bodies)
  double frames = 0.0;          // output frames
  double frameInterval = 0.0;   // 1 / fps, s
  double step = 0.0;            // the step at rest, s
  double blobVoxels = 0.0;      // per frame: sum over isotropic surfaced particles of (radius / voxel)^3
  double anisotropicBlobVoxels = 0.0;  // the same over particles surfaced by the anisotropic kernel
  double pixels = 0.0;          // width x height
  double samplesPerPixel = 0.0;
  bool whitted = false;         // the integrator: whitted, or path
  bool video = true;            // a video is encoded from the frames
  int threads = 2;
};

enum class Stage { Sim, Surface, Render, Encode, Count };
inline constexpr std::array<const char*, size_t(Stage::Count)> kStageNames{"sim", "surface", "render", "encode"};

struct RunEstimate {
  double steps = 0.0;
  std::array<double, size_t(Stage::Count)> seconds{};  // per Stage
  double totalSeconds() const;
};

// Time steps a frame takes: ceil(interval / step), a ratio within 1e-6 of a whole number taken
// as that number (the step that divides the interval exactly).
double stepsPerFrame(double frameInterval, double step);
RunEstimate estimateRun(const RunSize& size, const MachineSpeed& speed = kDevelopmentMachine);

// The run `scene` describes (after --quality), with `probe` the simulation it starts from (its
// particles and stability bound) and `threads` the threads it will run on.
RunSize runSize(const Scene& scene, const sim::Simulation& probe, int threads, bool video);

// While a run runs: each stage's seconds left, the model's until the stage is measured, then its
// measured seconds per frame times the frames it has left. A stage is measured by its first frame
// (the simulation's first frame with steps: the second it makes, the first being t = 0 or the
// resumed one); a later stage's start finishes the stages before it.
class RunForecast {
public:
  explicit RunForecast(const RunEstimate& model);
  // Told of each stage's progress (pipeline/progress.h; "sim", "surface", "render", "film"):
  // returns what was just measured ("sim frame 1: 9 steps in 0.47 s") when a stage's first frame
  // was, otherwise an empty string. Sets state.runSecondsLeft.
  std::string observe(ProgressState& state);
  // `stage` has `framesLeft` frames to go at `secondsPerFrame` each.
  void measured(Stage stage, double secondsPerFrame, double framesLeft);
  void finished(Stage stage);
  double secondsLeft(Stage stage) const;
  double totalSecondsLeft() const;
  // "sim 2.1 min, surface 0.2 min (model), render 1.4 min (model), encode 0.0 min (model); 3.7 min in all"
  std::string line() const;

private:
  std::array<double, size_t(Stage::Count)> left_{};
  std::array<bool, size_t(Stage::Count)> measured_{};
  // The simulation's first report after its start: items, seconds, steps (items < 0: none yet).
  int simItems_ = -1;
  double simSeconds_ = 0.0;
  long long simSteps_ = 0;
};

}  // namespace kurage::pipeline
