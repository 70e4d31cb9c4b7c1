// Checkpoints and --resume (issue 16): a resumed simulation continues bit for bit, a checkpoint
// that is damaged or not this scene's is an error naming it, and a run killed with SIGKILL at
// random moments, then resumed, leaves exactly the outputs of an uninterrupted run.
#include "pipeline/io/checkpoint.h"
#include "pipeline/io/files.h"
#include "pipeline/scene.h"
#include "pipeline/stages.h"
#include "sim/simulation.h"
#include "test_util.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstring>
#include <fcntl.h>
#include <random>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>

namespace kurage::pipeline {
namespace {

namespace fs = std::filesystem;
using kurage::test::TempDir;

const fs::path kJellyfish = test::sourceDir() / "tests/scenes/tiny_jellyfish.json";

// The tiny dam break under an incompressible solver with boundary particles, an emitter and a
// sink: every piece of state a fluid-only run carries (the solver's warm start, emitter progress,
// removed particles).
Scene incompressibleScene(const std::string& solver = "dfsph") {
  nlohmann::json doc = nlohmann::json::parse(readText(test::sourceDir() / "tests/scenes/tiny_dam_break.json"));
  doc.erase("$schema");
  doc["fluid"]["solver"] = solver;
  doc["container"]["wall_density"] = "boundary_particles";
  doc["emitters"] = nlohmann::json::parse(
      R"([{"position": [12, 2.5, 8], "direction": [0, 0, -1], "radius": 1.5, "speed": 4.0, "start": 0.0, "end": 0.9}])");
  doc["sinks"] = nlohmann::json::parse(R"([{"min": [0, 0, 0], "max": [2, 5, 2]}])");
  return parseScene(doc, solver + ".json");
}

void expectSameParticles(const sim::ParticleSet& a, const sim::ParticleSet& b) {
  ASSERT_EQ(a.size(), b.size());
  const auto same = [](const auto& x, const auto& y) {
    return x.size() == y.size() && std::memcmp(x.data(), y.data(), x.size() * sizeof(x[0])) == 0;
  };
  EXPECT_TRUE(same(a.x, b.x) && same(a.y, b.y) && same(a.z, b.z));
  EXPECT_TRUE(same(a.vx, b.vx) && same(a.vy, b.vy) && same(a.vz, b.vz));
  EXPECT_TRUE(same(a.density, b.density) && same(a.pressure, b.pressure) && same(a.restDensity, b.restDensity));
  EXPECT_TRUE(same(a.id, b.id) && same(a.kind, b.kind) && same(a.mass, b.mass));
}

TEST(Checkpoint, ARestoredSimulationContinuesBitForBit) {
  for (const Scene& scene : {loadScene(kJellyfish), incompressibleScene("dfsph"), incompressibleScene("iisph")}) {
    SCOPED_TRACE(scene.name + " " + scene.sim.fluid.solver.name());
    sim::Simulation straight(scene.sim), first(scene.sim);
    const double t1 = 0.5, t2 = 1.0;
    first.advanceTo(t1);
    sim::StateWriter state;
    first.saveState(state);
    sim::Simulation resumed(scene.sim);
    sim::StateReader reader(state.bytes());
    resumed.restoreState(reader);
    straight.advanceTo(t1);  // runs advance frame by frame: a step lands on every frame time
    straight.advanceTo(t2);
    resumed.advanceTo(t2);
    expectSameParticles(straight.particles(), resumed.particles());
    EXPECT_EQ(straight.stats().steps, resumed.stats().steps);
    EXPECT_EQ(straight.stats().emitted, resumed.stats().emitted);
    EXPECT_EQ(straight.stats().removed, resumed.stats().removed);
    EXPECT_EQ(straight.solver().counters().iterations(), resumed.solver().counters().iterations());
    EXPECT_GT(straight.solver().counters().steps, 0u);
    if (straight.bodies()) {
      EXPECT_EQ(straight.bodies()->stats().collisionPasses, resumed.bodies()->stats().collisionPasses);
    }
    if (scene.name == "tiny_dam_break") {
      EXPECT_GT(straight.stats().emitted, 0u);  // the pieces under test did act
      EXPECT_GT(straight.stats().removed, 0u);
    }
  }
}

TEST(Checkpoint, StateThatDoesNotFitTheSceneIsRefused) {
  const Scene scene = loadScene(kJellyfish);
  sim::Simulation simulation(scene.sim);
  simulation.advanceTo(0.25);
  sim::StateWriter state;
  simulation.saveState(state);
  const std::string bytes = state.bytes();
  sim::Simulation other(incompressibleScene().sim);
  sim::StateReader foreign(bytes);
  EXPECT_THROW(other.restoreState(foreign), sim::StateError);
  sim::Simulation same(scene.sim);
  sim::StateReader truncated(std::string_view(bytes).substr(0, bytes.size() / 2));
  EXPECT_THROW(same.restoreState(truncated), sim::StateError);
}

// Expects `call` to throw IoError naming `file` and containing `detail`.
template <class Call>
void expectErrorNaming(Call call, const fs::path& file, const std::string& detail) {
  try {
    call();
    ADD_FAILURE() << "no error for " << file;
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find(file.string()), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(detail), std::string::npos) << e.what();
  }
}

TEST(Checkpoint, DamagedOrForeignCheckpointsAreErrorsNamingTheFile) {
  TempDir dir;
  const fs::path file = dir.path() / "checkpoint.bin";
  const Checkpoint written{4, 0.5, std::string(1000, 'x'), "records"};
  writeCheckpoint(file, written, "00000000000000aa");
  const Checkpoint read = readCheckpoint(file, "00000000000000aa");
  EXPECT_EQ(read.frame, 4);
  EXPECT_EQ(read.time, 0.5);
  EXPECT_EQ(read.simState, written.simState);
  EXPECT_EQ(read.stageState, written.stageState);
  expectErrorNaming([&] { readCheckpoint(file, "00000000000000bb"); }, file, "other scene parameters");
  const std::string bytes = readFile(file);
  std::string flipped = bytes;
  flipped[bytes.size() - 10] ^= 0x20;
  writeFileAtomic(file, flipped);
  expectErrorNaming([&] { readCheckpoint(file, "00000000000000aa"); }, file, "damaged or truncated");
  writeFileAtomic(file, bytes.substr(0, bytes.size() - 7));
  expectErrorNaming([&] { readCheckpoint(file, "00000000000000aa"); }, file, "damaged or truncated");
  writeFileAtomic(file, "not a checkpoint");
  expectErrorNaming([&] { readCheckpoint(file, "00000000000000aa"); }, file, "not a kurage checkpoint");

  // Through the CLI: another scene's checkpoint is refused with exit 1, nothing resumed.
  const fs::path out = dir.path() / "out", log = dir.path() / "log.txt";
  ASSERT_EQ(test::runKurage("sim " + kJellyfish.string() + " -o " + out.string() + " --frames 0-1", log), 0);
  writeCheckpoint(out / "checkpoint.bin", written, "00000000000000aa");
  EXPECT_EQ(test::runKurage("sim " + kJellyfish.string() + " -o " + out.string() + " --resume", log), 1);
  EXPECT_NE(readText(log).find((out / "checkpoint.bin").string() + ": made from other scene parameters"),
            std::string::npos)
      << readText(log);
}

// A file's contents without what differs between identical runs: OpenVDB's random UUID (bytes
// 21-56 of the header) and the kurage:checksum that covers it.
std::string contentOf(const fs::path& file) {
  std::string bytes = readFile(file);
  if (file.extension() == ".vdb") {
    std::fill(bytes.begin() + 21, bytes.begin() + 57, '0');
    const size_t at = bytes.find("kurage:checksum");
    if (at != std::string::npos) std::fill_n(bytes.begin() + long(at + 15 + 4 + 6 + 4), 16, '0');
  }
  return bytes;
}

// Every file of OUT's stage folders, bodies.csv and sim_frames.csv, by relative path.
std::map<std::string, std::string> outputsOf(const fs::path& out) {
  std::map<std::string, std::string> files;
  for (const char* folder : {"particles", "surfaces", "frames"})
    for (const auto& entry : fs::directory_iterator(out / folder))
      files[std::string(folder) + "/" + entry.path().filename().string()] = contentOf(entry.path());
  files["bodies.csv"] = readFile(out / "bodies.csv");
  files["sim_frames.csv"] = readFile(out / "sim_frames.csv");
  return files;
}

TEST(Resume, SigtermWritesACheckpointAndTheResumedSimulationIsBitIdentical) {
  TempDir dir;
  const fs::path reference = dir.path() / "reference", out = dir.path() / "out", log = dir.path() / "log.txt";
  ASSERT_EQ(test::runKurage("sim " + kJellyfish.string() + " -o " + reference.string(), log), 0) << readText(log);
  // --checkpoint-every 0: the only checkpoint before the end is the one SIGTERM makes.
  const pid_t pid = test::startKurage({"sim", kJellyfish.string(), "-o", out.string(), "--checkpoint-every", "0"}, log);
  const auto start = std::chrono::steady_clock::now();
  while (!fs::exists(out / "particles/0002.vdb") && std::chrono::steady_clock::now() - start < std::chrono::seconds(60))
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  ::kill(pid, SIGTERM);
  const int code = test::waitFor(pid);
  if (code == 0) GTEST_SKIP() << "the simulation finished before SIGTERM arrived";
  EXPECT_EQ(code, 128 + SIGTERM) << readText(log);
  EXPECT_EQ(nlohmann::json::parse(readText(out / "run.json"))["status"], "interrupted");
  const Checkpoint c = readCheckpoint(out / "checkpoint.bin", stageHash(loadScene(kJellyfish), "sim"));
  EXPECT_GE(c.frame, 2);
  EXPECT_LT(c.frame, 6);
  ASSERT_EQ(test::runKurage("sim " + kJellyfish.string() + " -o " + out.string() + " --resume", log), 0) << readText(log);
  EXPECT_NE(readText(log).find("resuming after frame " + std::to_string(c.frame)), std::string::npos) << readText(log);
  for (int f = 0; f < 7; ++f) {
    const fs::path name = frameFile("particles", f, "vdb");
    EXPECT_EQ(contentOf(out / name), contentOf(reference / name)) << name;
  }
  EXPECT_EQ(readFile(out / "bodies.csv"), readFile(reference / "bodies.csv"));
  EXPECT_EQ(readFile(out / "sim_frames.csv"), readFile(reference / "sim_frames.csv"));
  const nlohmann::json ran = nlohmann::json::parse(readText(out / "run.json"));
  EXPECT_EQ(ran["stages"]["sim"]["resumed_after_frame"], c.frame);
  EXPECT_EQ(ran["stages"]["sim"]["steps"], nlohmann::json::parse(readText(reference / "run.json"))["stages"]["sim"]["steps"]);
}

TEST(Resume, SigkillAtTenMomentsAcrossTheRunThenResumeLeavesTheUninterruptedRunsOutputs) {
  TempDir dir;
  const fs::path reference = dir.path() / "reference", log = dir.path() / "log.txt";
  const auto start = std::chrono::steady_clock::now();
  ASSERT_EQ(test::runKurage("run " + kJellyfish.string() + " -o " + reference.string() + " --threads 2", log), 0)
      << readText(log);
  double length = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  // 10 trials: a fresh run killed at a random moment of the k-th tenth of 2-95 % of its length,
  // so that each part of the run (the simulation's frames and checkpoints, the surfaces, the
  // frames, the movie) sees a kill, then resumed to the end. The length is the reference's,
  // unless a trial ends before its moment: then that trial's length is used from there on, so
  // the range only shrinks (the reference may have shared the machine with another test). A
  // trial killed early may not have made its folder yet.
  std::mt19937 rng(20261125);
  std::uniform_real_distribution<double> within(0.0, 1.0);
  const int trials = 10;
  const auto argsFor = [&](const fs::path& folder) {
    return std::vector<std::string>{"run", kJellyfish.string(), "-o", folder.string(), "--threads", "2", "--resume",
                                    "--checkpoint-every", "1"};
  };
  const std::map<std::string, std::string> expected = outputsOf(reference);
  int killed = 0;
  for (int k = 0; k < trials; ++k) {
    const fs::path trial = dir.path() / ("trial" + std::to_string(k));
    const pid_t pid = test::startKurage(argsFor(trial), log);
    const auto began = std::chrono::steady_clock::now();
    const double at = length * (0.02 + 0.93 * (k + within(rng)) / trials);
    const auto since = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - began).count(); };
    bool ended = false;  // reaped before its moment (then it must not be signalled)
    int status = 0;
    while (!ended && since() < at) {
      const pid_t reaped = ::waitpid(pid, &status, WNOHANG);
      ASSERT_NE(reaped, -1) << std::strerror(errno);
      ended = reaped == pid;
      if (!ended) std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    if (ended) {
      ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "a trial failed on its own\n" << readText(log);
      length = since();
    } else {
      ::kill(pid, SIGKILL);
      if (test::waitFor(pid) == 128 + SIGKILL) ++killed;
    }
    ASSERT_EQ(test::waitFor(test::startKurage(argsFor(trial), log)), 0) << readText(log);
    EXPECT_EQ(outputsOf(trial), expected) << (ended ? "ended before its moment, " : "killed at ") << at << " s";
    EXPECT_EQ(nlohmann::json::parse(readText(trial / "run.json"))["status"], "complete");
    for (const auto& entry : fs::recursive_directory_iterator(trial))
      EXPECT_NE(entry.path().extension(), ".tmp") << "left behind: " << entry.path();
    if (k < trials - 1) fs::remove_all(trial);
  }
  EXPECT_GE(killed, trials - 2);
  const fs::path out = dir.path() / ("trial" + std::to_string(trials - 1));
  const std::vector<std::string> args = argsFor(out);
  // A further resume redoes nothing: the simulation is at its last frame, the frames and the
  // movie are up to date.
  const fs::path again = dir.path() / "again.txt";
  const auto movieTime = fs::last_write_time(out / "tiny_jellyfish.mp4");
  ASSERT_EQ(test::waitFor(test::startKurage(args, again)), 0) << readText(again);
  EXPECT_NE(readText(again).find("resuming after frame 6"), std::string::npos) << readText(again);
  EXPECT_NE(readText(again).find("(up to date"), std::string::npos) << readText(again);
  EXPECT_EQ(fs::last_write_time(out / "tiny_jellyfish.mp4"), movieTime);
  EXPECT_EQ(nlohmann::json::parse(readText(out / "run.json"))["stages"]["render"]["frames_skipped"], 7);
}

}  // namespace
}  // namespace kurage::pipeline
