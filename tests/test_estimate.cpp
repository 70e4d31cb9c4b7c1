// The run-time estimate's arithmetic (pipeline/estimate.h): steps a frame, each stage's seconds
// from the model's terms, the scaling by threads, and the forecast a run updates from its first
// measured frames.
#include "pipeline/estimate.h"

#include <gtest/gtest.h>

using namespace kurage::pipeline;

namespace {

// Round figures, so that each stage's seconds can be worked out by hand.
constexpr MachineSpeed kRound{"test", 2, 1e-6, 1e-8, 2.0, 1e-6, 2e-6, 1e-7};

RunSize roundSize() {
  RunSize s;
  s.particles = 1000;
  s.frames = 11;
  s.frameInterval = 0.1;
  s.step = 0.03;  // 4 steps a frame
  s.blobVoxels = 1e5;
  s.anisotropicBlobVoxels = 1e4;
  s.pixels = 1e4;
  s.samplesPerPixel = 4;
  s.whitted = true;
  s.video = true;
  s.threads = 2;
  return s;
}

double at(const RunEstimate& e, Stage s) { return e.seconds[size_t(s)]; }

}  // namespace

TEST(Estimate, StepsPerFrameRoundUpExceptWholeRatios) {
  EXPECT_EQ(stepsPerFrame(0.1, 0.03), 4.0);
  EXPECT_EQ(stepsPerFrame(1.0 / 24.0, 0.009594), 5.0);       // the jellyfish at 24 fps
  EXPECT_EQ(stepsPerFrame(1.0 / 12.0, 0.009594), 9.0);       // and at its preview's 12
  EXPECT_EQ(stepsPerFrame(1.0 / 24.0, 1.0 / 240.0), 10.0);   // a whole ratio in floating point
  EXPECT_EQ(stepsPerFrame(0.1, 0.2), 1.0);                   // a step longer than the frame: one
  EXPECT_EQ(stepsPerFrame(0.1, 0.0), 0.0);
}

TEST(Estimate, EachStageIsItsTermOfTheModel) {
  const RunEstimate e = estimateRun(roundSize(), kRound);
  EXPECT_DOUBLE_EQ(e.steps, 40.0);                                   // (11 - 1) frames x 4 steps
  EXPECT_DOUBLE_EQ(at(e, Stage::Sim), 1000 * 40 * 1e-6);             // particle-steps
  EXPECT_DOUBLE_EQ(at(e, Stage::Surface), 11 * 1e-8 * (1e5 + 2.0 * 1e4));
  EXPECT_DOUBLE_EQ(at(e, Stage::Render), 11 * 1e4 * 4 * 1e-6);       // whitted samples
  EXPECT_DOUBLE_EQ(at(e, Stage::Encode), 11 * 1e4 * 1e-7);
  EXPECT_DOUBLE_EQ(e.totalSeconds(), at(e, Stage::Sim) + at(e, Stage::Surface) + at(e, Stage::Render) +
                                         at(e, Stage::Encode));
  RunSize path = roundSize();
  path.whitted = false;
  path.video = false;
  const RunEstimate p = estimateRun(path, kRound);
  EXPECT_DOUBLE_EQ(at(p, Stage::Render), 11 * 1e4 * 4 * 2e-6);
  EXPECT_EQ(at(p, Stage::Encode), 0.0);
}

TEST(Estimate, MoreThreadsThanTheMachinesScaleTheSecondsDown) {
  RunSize four = roundSize();
  four.threads = 4;
  const RunEstimate two = estimateRun(roundSize(), kRound), quick = estimateRun(four, kRound);
  EXPECT_EQ(quick.steps, two.steps);
  for (size_t s = 0; s < size_t(Stage::Count); ++s) EXPECT_DOUBLE_EQ(quick.seconds[s], two.seconds[s] / 2.0) << s;
}

TEST(Estimate, ForecastTakesEachStageFromItsFirstFrame) {
  RunEstimate model;
  model.seconds = {100.0, 10.0, 50.0, 1.0};
  RunForecast f(model);
  EXPECT_DOUBLE_EQ(f.totalSecondsLeft(), 161.0);
  EXPECT_NE(f.line().find("sim 1.7 min (model)"), std::string::npos) << f.line();
  // The sim: frame 0 (t = 0, no steps), then frame 1: 9 steps in 0.5 s, 9 frames left.
  ProgressState s{"sim", 0, 11, 0.0};
  EXPECT_EQ(f.observe(s), "");
  s = {"sim", 1, 11, 0.1, -1.0, 0};
  EXPECT_EQ(f.observe(s), "");
  EXPECT_DOUBLE_EQ(f.secondsLeft(Stage::Sim), 100.0) << "frame 0 takes no steps: not a measure";
  s = {"sim", 2, 11, 0.6, -1.0, 9};
  EXPECT_EQ(f.observe(s), "sim frame 1: 9 steps in 0.50 s");
  EXPECT_DOUBLE_EQ(f.secondsLeft(Stage::Sim), 9 * 0.5);
  EXPECT_DOUBLE_EQ(s.runSecondsLeft, 4.5 + 10.0 + 50.0 + 1.0);
  EXPECT_NE(f.line().find("sim 0.1 min, surface 0.2 min (model)"), std::string::npos) << f.line();
  // The surface's start ends the sim; its first of 11 frames takes 2 s.
  s = {"surface", 0, 11, 0.0};
  f.observe(s);
  EXPECT_EQ(f.secondsLeft(Stage::Sim), 0.0);
  s = {"surface", 1, 11, 2.0};
  EXPECT_EQ(f.observe(s), "surface: first frame in 2.00 s");
  EXPECT_DOUBLE_EQ(f.secondsLeft(Stage::Surface), 20.0);
  EXPECT_DOUBLE_EQ(f.totalSecondsLeft(), 20.0 + 50.0 + 1.0);
  // Later frames follow the stage's own rate, and its last frame ends it.
  s = {"surface", 5, 11, 8.0, 9.6};
  EXPECT_EQ(f.observe(s), "");
  EXPECT_DOUBLE_EQ(f.secondsLeft(Stage::Surface), 9.6);
  s = {"surface", 11, 11, 20.0, 0.0};
  f.observe(s);
  EXPECT_EQ(f.secondsLeft(Stage::Surface), 0.0);
  // The film's start ends the render.
  s = {"film", 0, 1, 0.0};
  f.observe(s);
  EXPECT_DOUBLE_EQ(s.runSecondsLeft, 1.0);
}
