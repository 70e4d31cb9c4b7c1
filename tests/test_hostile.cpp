// Hostile inputs and the moments between stages (docs/design/reliability.md lists which test proves which
// promise): each test is one class of ways a run failed when probed as a hostile user would,
// through the library where that is enough and through build/kurage where the promise is the
// command's (its exit status, what it leaves in OUT).
#include "pipeline/exports.h"
#include "pipeline/io/checkpoint.h"
#include "pipeline/farm/farm.h"
#include "pipeline/io/files.h"
#include "pipeline/io/json_file.h"
#include "pipeline/io/run_lock.h"
#include "pipeline/scene.h"
#include "pipeline/sim_frame.h"
#include "pipeline/stages.h"
#include "sim/simulation.h"
#include "test_util.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <csignal>
#include <fstream>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>

namespace kurage::pipeline {
namespace {

namespace fs = std::filesystem;
using kurage::test::TempDir;
using kurage::test::temporariesIn;
using Clock = std::chrono::steady_clock;

const fs::path kTinyScene = test::sourceDir() / "tests/scenes/tiny_dam_break.json";

// Runs build/kurage with `args` (no shell between: newlines and quotes reach it as they are).
int run(const std::vector<std::string>& args, const fs::path& log, const test::StartOptions& options = {}) {
  fs::remove(log);
  return test::waitFor(test::startKurage(args, log, options));
}

// Runs build/kurage under `timeout 30`, so that a run that blocks fails the test instead of
// hanging the suite: 124 means it blocked.
int runBounded(const std::string& arguments, const fs::path& log) {
  const std::string command = "timeout 30 " + (test::binaryDir() / "kurage").string() + " " + arguments + " > " +
                              log.string() + " 2>&1";
  const int status = std::system(command.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// The tiny scene with edits (JSON pointer -> value), written to `dir`/NAME.json.
fs::path tinyWith(const fs::path& dir, const std::string& name,
                  const std::vector<std::pair<std::string, nlohmann::json>>& edits) {
  nlohmann::json doc = nlohmann::json::parse(readText(kTinyScene));
  doc.erase("$schema");
  for (const auto& [pointer, value] : edits) doc[nlohmann::json::json_pointer(pointer)] = value;
  const fs::path file = dir / (name + ".json");
  writeTextAtomic(file, doc.dump());
  return file;
}

bool waitForFile(const fs::path& file, std::chrono::seconds limit) {
  const auto start = Clock::now();
  while (!fs::exists(file)) {
    if (Clock::now() - start > limit) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return true;
}

double secondsSince(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

std::string runStatus(const fs::path& out) { return nlohmann::json::parse(readText(out / "run.json")).value("status", ""); }

// Sends SIGTERM to a running kurage (started by startKurage) and expects it to stop within 3 s,
// exit 128 + SIGTERM saying so, and, given `out`, run.json "interrupted" and no temporary in it.
void expectStoppedBySigterm(pid_t pid, const fs::path& log, const fs::path& out) {
  const auto signalled = Clock::now();
  ::kill(pid, SIGTERM);
  int status = 0;
  ASSERT_EQ(::waitpid(pid, &status, 0), pid);
  EXPECT_LT(secondsSince(signalled), 3.0) << "the work went on after the signal";
  ASSERT_TRUE(WIFEXITED(status)) << "killed by the signal, not stopped: " << readText(log);
  EXPECT_EQ(WEXITSTATUS(status), 128 + SIGTERM) << readText(log);
  EXPECT_TRUE(contains(readText(log), "interrupted by SIGTERM")) << readText(log);
  if (out.empty()) return;
  EXPECT_EQ(runStatus(out), "interrupted");
  EXPECT_TRUE(temporariesIn(out).empty());
}

// ---- 1. nesting depth -------------------------------------------------------------------------

TEST(HostileJson, NestingDeeperThanTheLimitIsRefusedBeforeParsing) {
  TempDir dir;
  // 200,000 levels under "name" (400 KB): refused from the text, in linear time and memory.
  const std::string deep = "{\"name\": " + std::string(200000, '[') + std::string(200000, ']') + "}";
  try {
    parseStrictJson(deep, "deep.json");
    ADD_FAILURE() << "accepted";
  } catch (const SceneError& e) {
    EXPECT_TRUE(contains(e.what(), "deep.json")) << e.what();
    EXPECT_TRUE(contains(e.what(), "nested deeper than 64 levels at line 1, column 73")) << e.what();
  }
  // 64 levels are a scene error of another kind (the loader's), not of the parser.
  const std::string at64 = "{\"name\": " + std::string(63, '[') + std::string(63, ']') + "}";
  EXPECT_NO_THROW(parseStrictJson(at64, "ok.json"));
  // Brackets inside strings are text.
  EXPECT_EQ(jsonDepthBeyond("{\"a\": \"" + std::string(1000, '[') + "\"}"), std::string_view::npos);
  EXPECT_EQ(jsonDepthBeyond("[[[\"\\\"[\"]]]", 3), std::string_view::npos);
  EXPECT_EQ(jsonDepthBeyond("[[[[]]]]", 3), 3u);

  // The command: exit 2 naming the file, in little memory (linear in the text).
  const fs::path file = dir.path() / "deep.json";
  writeTextAtomic(file, deep);
  const fs::path log = dir.path() / "log.txt";
  const pid_t pid = test::startKurage({"check", file.string()}, log);
  int status = 0;
  rusage usage{};
  ASSERT_EQ(::wait4(pid, &status, 0, &usage), pid);
  ASSERT_TRUE(WIFEXITED(status)) << readText(log);
  EXPECT_EQ(WEXITSTATUS(status), 2) << readText(log);
  EXPECT_TRUE(contains(readText(log), file.string() + ": (top level): nested deeper than 64")) << readText(log);
  EXPECT_LT(usage.ru_maxrss, 400 * 1024) << "KB";

  // Files kurage wrote itself (run.json, farm records) are read with the same limit.
  writeTextAtomic(dir.path() / "run.json", "{\"stages\": " + std::string(100, '[') + std::string(100, ']') + "}");
  test::expectErrorNamingPath([&] { readJson(dir.path() / "run.json"); }, dir.path() / "run.json", "nested deeper");
}

TEST(HostileJson, ValuesInMessagesAreExcerptsOfBoundedLength) {
  const std::string huge(5 << 20, 'x');
  EXPECT_LT(jsonExcerpt(huge).size(), 120u);
  EXPECT_TRUE(contains(jsonExcerpt(huge), "(5242880 bytes)"));
  nlohmann::json wide = nlohmann::json::array();
  for (int i = 0; i < 100000; ++i) wide.push_back(i);
  EXPECT_LT(jsonExcerpt(wide).size(), 120u);
  EXPECT_TRUE(contains(jsonExcerpt(wide), "(100000 items)"));
  nlohmann::json deep = 1;
  for (int i = 0; i < 1000; ++i) deep = nlohmann::json::array({deep});  // built in code, past the parser's limit
  EXPECT_TRUE(contains(jsonExcerpt(deep), "[...]"));
  EXPECT_EQ(jsonExcerpt(nlohmann::json::parse(R"({"a": [1, "b"]})")), R"({"a": [1, "b"]})");
  // A cut never splits a UTF-8 character.
  EXPECT_EQ(textExcerpt("\xc3\xa9\xc3\xa9", 3), "\xc3\xa9... (4 bytes)");
}

// ---- 2. links where kurage writes -------------------------------------------------------------

TEST(HostileLinks, FoldersUnderOutAreRealFoldersOrTheRunRefusesNamingThem) {
  TempDir dir;
  const fs::path out = dir.path() / "out", outside = dir.path() / "outside";
  fs::create_directories(outside);
  EXPECT_EQ(outputFolder(out, "exports/fluid"), out / "exports/fluid");
  EXPECT_TRUE(fs::is_directory(out / "exports/fluid"));
  fs::create_directory_symlink(outside, out / "frames");
  test::expectErrorNamingPath([&] { outputFolder(out, "frames"); }, out / "frames", "symbolic link");
  fs::create_directory_symlink(outside, out / "exports/bell");
  test::expectErrorNamingPath([&] { outputFolder(out, "exports/bell/deeper"); }, out / "exports/bell", "symbolic link");
  writeTextAtomic(out / "particles", "a file");
  test::expectErrorNamingPath([&] { outputFolder(out, "particles"); }, out / "particles", "not a folder");
  EXPECT_THROW(outputFolder(out, "../escape"), IoError);
  EXPECT_THROW(outputFolder(out, "/tmp"), IoError);
  EXPECT_TRUE(fs::is_empty(outside));
  // OUT itself may be a link: the user chose it.
  fs::create_directory_symlink(outside, dir.path() / "linked-out");
  EXPECT_EQ(outputFolder(dir.path() / "linked-out", "frames"), dir.path() / "linked-out/frames");
  EXPECT_TRUE(fs::is_directory(outside / "frames"));
}

TEST(HostileLinks, StagesNeverWriteThroughALinkInOut) {
  TempDir dir;
  const fs::path out = dir.path() / "out", outside = dir.path() / "outside", log = dir.path() / "log.txt";
  fs::create_directories(out);
  fs::create_directories(outside);
  const std::vector<std::string> scene{kTinyScene.string(), "-o", out.string(), "--threads", "2"};
  const auto stage = [&](const std::string& name, std::vector<std::string> extra = {}) {
    std::vector<std::string> args{name};
    args.insert(args.end(), scene.begin(), scene.end());
    args.insert(args.end(), extra.begin(), extra.end());
    return run(args, log);
  };
  // The run lock as a link to a file outside OUT: refused, the file untouched.
  writeTextAtomic(outside / "precious.txt", "precious");
  fs::create_symlink(outside / "precious.txt", out / ".kurage.lock");
  EXPECT_EQ(stage("sim"), 1) << readText(log);
  EXPECT_TRUE(contains(readText(log), (out / ".kurage.lock").string() + ": cannot open the run lock: it is a symbolic link"))
      << readText(log);
  EXPECT_EQ(readText(outside / "precious.txt"), "precious");
  fs::remove(out / ".kurage.lock");
  fs::remove(outside / "precious.txt");
  // Each stage's folder as a link to a folder outside OUT.
  fs::create_directory_symlink(outside, out / "particles");
  EXPECT_EQ(stage("sim"), 1) << readText(log);
  EXPECT_TRUE(contains(readText(log), (out / "particles").string() + ": is a symbolic link")) << readText(log);
  fs::remove(out / "particles");
  ASSERT_EQ(stage("sim"), 0) << readText(log);
  ASSERT_EQ(stage("surface"), 0) << readText(log);
  fs::create_directory_symlink(outside, out / "frames");
  EXPECT_EQ(stage("render", {"--no-video"}), 1) << readText(log);
  EXPECT_TRUE(contains(readText(log), (out / "frames").string() + ": is a symbolic link")) << readText(log);
  fs::create_directory_symlink(outside, out / "exports");
  EXPECT_EQ(run({"export", out.string(), "--format", "particles_ply"}, log), 1) << readText(log);
  EXPECT_TRUE(contains(readText(log), (out / "exports").string() + ": is a symbolic link")) << readText(log);
  EXPECT_TRUE(fs::is_empty(outside)) << "nothing written outside OUT";
}

// ---- 3. values that reach the farm's scripts --------------------------------------------------

TEST(HostileFarm, ControlCharactersAndForeignCharactersInScriptValuesAreRefused) {
  TempDir dir;
  const fs::path log = dir.path() / "log.txt";
  const fs::path out = dir.path() / "out";
  const auto farm = [&](std::vector<std::string> extra, const fs::path& o) {
    std::vector<std::string> args{"farm", kTinyScene.string(), "-o", o.string()};
    args.insert(args.end(), extra.begin(), extra.end());
    return run(args, log);
  };
  const std::string injected = "\ntouch " + (dir.path() / "PWNED").string() + "\n";
  const std::vector<std::pair<std::vector<std::string>, std::string>> refused{
      {{"--partition", "gpu" + injected}, "--partition"},
      {{"--partition", "gpu;touch PWNED"}, "--partition"},
      {{"--partition", "gpu $(touch PWNED)"}, "--partition"},
      {{"--time-limit", "1:00" + injected}, "--time-limit"},
      {{"--time-limit", "1:00`touch PWNED`"}, "--time-limit"},
      {{"--sbatch-arg", "--mem=1G" + injected}, "--sbatch-arg"},
      {{"--sbatch-arg", "--mem=1G\rtouch PWNED"}, "--sbatch-arg"}};
  for (const auto& [extra, flag] : refused) {
    EXPECT_EQ(farm(extra, out), 2) << extra[1] << "\n" << readText(log);
    EXPECT_TRUE(contains(readText(log), flag + ":")) << readText(log);
  }
  EXPECT_EQ(farm({}, dir.path() / ("out" + injected)), 2) << readText(log);
  EXPECT_TRUE(contains(readText(log), "-o: OUT must not contain control characters")) << readText(log);
  EXPECT_FALSE(fs::exists(out / "farm")) << "a refused plan writes nothing";
  EXPECT_FALSE(fs::exists(dir.path() / "PWNED"));
  // Letters, digits and the characters Slurm uses are accepted.
  EXPECT_EQ(farm({"--partition", "gpu-a100,cpu_2", "--time-limit", "1-12:00:00"}, out), 0) << readText(log);
}

TEST(HostileFarm, ShellAndSbatchMetacharactersReachTheProgramAsPlainText) {
  TempDir dir;
  const fs::path log = dir.path() / "log.txt";
  // Every character that means something to bash or to sbatch's directive reader, in OUT.
  const std::string hostile = "o u'\"$(touch PWNED)`touch PWNED2`;& #%j\\x|*";
  const fs::path out = dir.path() / hostile;
  ASSERT_EQ(run({"farm", kTinyScene.string(), "-o", out.string(), "--frames-per-task", "2"}, log), 0) << readText(log);
  const std::string sim = readText(out / "farm/sim.sbatch");
  // sbatch's reader: double quotes group, a backslash escapes the next character, % is doubled.
  std::string expected = "#SBATCH --output=\"";
  for (const char c : (out / "farm/logs").string() + "/") {
    if (c == '\\' || c == '"') expected += '\\';
    expected += c;
    if (c == '%') expected += '%';
  }
  EXPECT_TRUE(contains(sim, expected + "sim-%j.out\"\n")) << sim;

  // The scripts run by bash, with a stand-in for kurage that writes its arguments one per line:
  // every argument arrives whole, nothing else runs.
  const fs::path stub = dir.path() / "stub.sh", arguments = dir.path() / "arguments.txt";
  writeTextAtomic(stub, "#!/bin/bash\nprintf '%s\\n' \"$@\" >> '" + arguments.string() + "'\n");
  fs::permissions(stub, fs::perms::owner_all);
  FarmPlan plan = planFromJson(readJson(out / "farm/plan.json"), "plan.json");
  plan.kurage = stub;
  plan.sceneFile = dir.path() / "a scene; $(touch PWNED3).json";
  for (const auto& [name, script] : {std::pair{"sim", simScript(plan)}, std::pair{"frames", framesScript(plan)},
                                     std::pair{"merge", mergeScript(plan)}}) {
    const fs::path file = dir.path() / (std::string(name) + ".sh");
    writeTextAtomic(file, script);
    const std::string command = "cd '" + dir.path().string() + "' && SLURM_ARRAY_TASK_ID=1 bash " + file.string() +
                                " > " + log.string() + " 2>&1";
    EXPECT_EQ(std::system(command.c_str()), 0) << name << ": " << readText(log);
  }
  const std::string got = readText(arguments);
  EXPECT_TRUE(contains(got, "\n-o\n" + out.string() + "\n")) << got;
  EXPECT_TRUE(contains(got, "sim\n" + plan.sceneFile.string() + "\n")) << got;
  EXPECT_TRUE(contains(got, "--frames\n2-3\n--task\nsurface-2-3\n")) << got;
  EXPECT_TRUE(contains(got, "farm\nmerge\n" + out.string() + "\n")) << got;
  for (const char* marker : {"PWNED", "PWNED2", "PWNED3"}) EXPECT_FALSE(fs::exists(dir.path() / marker)) << marker;
  EXPECT_FALSE(fs::exists(fs::current_path() / "PWNED"));
}

// ---- 4. signals in the last frame and during the encode ---------------------------------------

TEST(HostileSignals, SigtermDuringTheLastFrameEndsTheRunInterrupted) {
  TempDir dir;
  const fs::path out = dir.path() / "out", log = dir.path() / "log.txt";
  const std::vector<std::string> scene{kTinyScene.string(), "-o", out.string(), "--threads", "2"};
  ASSERT_EQ(run({"sim", scene[0], scene[1], scene[2]}, log), 0) << readText(log);
  ASSERT_EQ(run({"surface", scene[0], scene[1], scene[2]}, log), 0) << readText(log);
  fs::remove(out / "run.json");
  // One frame, the last, long on purpose (minutes: 320 x 240 at 4096 samples on one thread); the
  // signal once the run has started (run.json) and the frame with it.
  const pid_t pid = test::startKurage({"render", kTinyScene.string(), "-o", out.string(), "--frames", "4",
                                       "--width", "320", "--height", "240", "--spp", "4096", "--no-video",
                                       "--threads", "1"},
                                      log);
  ASSERT_TRUE(waitForFile(out / "run.json", std::chrono::seconds(60)));
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  expectStoppedBySigterm(pid, log, out);
  EXPECT_FALSE(fs::exists(out / "frames/0004.png"));
}

// A stand-in for ffmpeg that says where it is (its pid in `marker`) and takes a minute.
fs::path slowFfmpeg(const fs::path& dir, const fs::path& marker) {
  const fs::path bin = dir / "bin";
  fs::create_directories(bin);
  writeTextAtomic(bin / "ffmpeg", "#!/bin/sh\necho $$ > '" + marker.string() + ".tmp'\nmv '" + marker.string() +
                                      ".tmp' '" + marker.string() + "'\nexec sleep 60\n");
  fs::permissions(bin / "ffmpeg", fs::perms::owner_all);
  return bin;
}

TEST(HostileSignals, SignalsDuringTheEncodeStopFfmpegAndSayInterrupted) {
  TempDir dir;
  const fs::path out = dir.path() / "out", log = dir.path() / "log.txt", marker = dir.path() / "ffmpeg.pid";
  const fs::path bin = slowFfmpeg(dir.path(), marker);
  test::StartOptions options;
  options.environment = {{"PATH", bin.string() + ":" + std::getenv("PATH")}};
  // SIGTERM to kurage alone: it ends ffmpeg and stops.
  for (const bool group : {false, true}) {
    SCOPED_TRACE(group ? "SIGINT to the process group (Ctrl-C)" : "SIGTERM to kurage");
    fs::remove(marker);
    options.ownProcessGroup = group;
    const pid_t pid = test::startKurage({"run", kTinyScene.string(), "-o", out.string(), "--threads", "2"}, log, options);
    ASSERT_TRUE(waitForFile(marker, std::chrono::seconds(120))) << readText(log);
    const pid_t ffmpeg = std::stoi(readText(marker));
    const auto signalled = Clock::now();
    ::kill(group ? -pid : pid, group ? SIGINT : SIGTERM);
    int status = 0;
    ASSERT_EQ(::waitpid(pid, &status, 0), pid);
    EXPECT_LT(secondsSince(signalled), 3.0);
    ASSERT_TRUE(WIFEXITED(status)) << readText(log);
    EXPECT_EQ(WEXITSTATUS(status), 128 + (group ? SIGINT : SIGTERM)) << readText(log);
    EXPECT_TRUE(contains(readText(log), group ? "interrupted by SIGINT" : "interrupted by SIGTERM")) << readText(log);
    EXPECT_EQ(runStatus(out), "interrupted");
    EXPECT_FALSE(fs::exists(out / "tiny_dam_break.mp4"));
    EXPECT_TRUE(temporariesIn(out).empty());
    EXPECT_NE(::kill(ffmpeg, 0), 0) << "ffmpeg outlived kurage";
  }
}

// ---- 5. special files -------------------------------------------------------------------------

TEST(HostileSpecialFiles, FifosAreErrorsNamingThemNeverWaitedOn) {
  TempDir dir;
  const fs::path out = dir.path() / "out", log = dir.path() / "log.txt";
  const auto fifo = [](const fs::path& p) {
    fs::remove(p);
    ASSERT_EQ(::mkfifo(p.c_str(), 0644), 0) << p;
  };
  const std::string scene = kTinyScene.string() + " -o " + out.string() + " --threads 2";
  const auto expectRefused = [&](const std::string& args, int code, const fs::path& named) {
    EXPECT_EQ(runBounded(args, log), code) << args << "\n" << readText(log);
    EXPECT_TRUE(contains(readText(log), named.string() + ": not a regular file")) << readText(log);
  };
  fifo(dir.path() / "scene.json");
  expectRefused("check " + (dir.path() / "scene.json").string(), 2, dir.path() / "scene.json");
  fs::create_directories(out);
  fifo(out / ".kurage.lock");
  EXPECT_EQ(runBounded("sim " + scene, log), 1) << readText(log);
  EXPECT_TRUE(contains(readText(log), "the run lock is not a regular file")) << readText(log);
  fs::remove(out / ".kurage.lock");
  ASSERT_EQ(runBounded("sim " + scene, log), 0) << readText(log);
  fifo(out / "checkpoint.bin");
  expectRefused("sim --resume " + scene, 1, out / "checkpoint.bin");
  fifo(out / "particles/0002.vdb");
  expectRefused("surface " + scene, 1, out / "particles/0002.vdb");
  ASSERT_EQ(runBounded("sim " + scene, log), 0) << readText(log);
  ASSERT_EQ(runBounded("surface " + scene, log), 0) << readText(log);
  // A frame that is a FIFO is not a frame: made again, in its place.
  fs::create_directories(out / "frames");
  fifo(out / "frames/0001.png");
  EXPECT_EQ(runBounded("render --no-video " + scene, log), 0) << readText(log);
  EXPECT_TRUE(fs::is_regular_file(out / "frames/0001.png"));
  // An environment image that is a FIFO.
  fifo(dir.path() / "sky.png");
  const fs::path sky = tinyWith(dir.path(), "sky", {{"/render/environment", {{"type", "image"}, {"image", (dir.path() / "sky.png").string()}}}});
  expectRefused("render --no-video --force " + sky.string() + " -o " + out.string(), 1, dir.path() / "sky.png");
}

// ---- 6. unbounded work ------------------------------------------------------------------------

TEST(HostileWork, StepCountsAboveTheLimitAreRefusedNamingTheKey) {
  TempDir dir;
  const fs::path log = dir.path() / "log.txt";
  const fs::path fixed = tinyWith(dir.path(), "fixed", {{"/time_step", {{"mode", "fixed"}, {"fixed_step", 1e-9}}}});
  EXPECT_EQ(run({"check", fixed.string()}, log), 2) << readText(log);
  EXPECT_TRUE(contains(readText(log), "time_step.fixed_step: gives at least 1e+09 time steps")) << readText(log);
  EXPECT_EQ(run({"check", fixed.string(), "--force"}, log), 0) << readText(log);
  const fs::path adaptive = tinyWith(dir.path(), "adaptive", {{"/time_step/max_step", 1e-9}, {"/time_step/min_step", 1e-10}});
  EXPECT_EQ(run({"check", adaptive.string()}, log), 2) << readText(log);
  EXPECT_TRUE(contains(readText(log), "time_step.max_step: gives at least 1e+09")) << readText(log);
  EXPECT_EQ(estimateSteps(loadScene(kTinyScene), 1.0), 20.0);  // 1 s at the default max_step of 0.05 s
  // still --time T: the steps to T.
  EXPECT_EQ(run({"still", kTinyScene.string(), "--time", "1e300", "-o", (dir.path() / "still.png").string()}, log), 2)
      << readText(log);
  EXPECT_TRUE(contains(readText(log), "--time 1e+300: simulating to it takes at least")) << readText(log);
  EXPECT_FALSE(fs::exists(dir.path() / "still.png"));
  // Past the limit with --force (2e8 steps), a signal still ends it.
  const pid_t pid = test::startKurage({"still", kTinyScene.string(), "--time", "1e7", "--force", "-o",
                                       (dir.path() / "still.png").string(), "--threads", "2"},
                                      log);
  std::this_thread::sleep_for(std::chrono::seconds(2));
  expectStoppedBySigterm(pid, log, {});
  EXPECT_FALSE(fs::exists(dir.path() / "still.png"));
}

// How advanceTo(t) ended: "stopped" (a whole step's state), "cut short" or "not stopped".
std::string stopAdvancing(sim::Simulation& simulation, double t) {
  try {
    simulation.advanceTo(t);
  } catch (const sim::Stopped& e) {
    return e.cutShort() ? "cut short" : "stopped";
  }
  return "not stopped";
}

// Every pressure solver's run ends within one step, or one iteration of its solve, of a stop
// check turning true: a step count that no check bounds (--force, a step that falls to min_step)
// still stops. Stopped after a step, the state continues bit for bit.
TEST(HostileWork, StopChecksEndTheSimulationAfterAStepOrInASolve) {
  for (const std::string solver : {"wcsph", "dfsph", "iisph"}) {
    SCOPED_TRACE(solver);
    nlohmann::json doc = nlohmann::json::parse(readText(kTinyScene));
    doc.erase("$schema");
    if (solver != "wcsph") {
      doc["fluid"].erase("pressure_stiffness");
      doc["fluid"]["solver"] = solver;
    }
    const Scene scene = parseScene(doc, "edited.json");
    sim::Simulation reference(scene.sim);
    reference.advanceTo(0.25);
    sim::Simulation stopped(scene.sim);
    int steps = 0;
    stopped.setStopChecks([&] { return ++steps == 3; });
    EXPECT_EQ(stopAdvancing(stopped, 0.25), "stopped");
    EXPECT_EQ(steps, 3);
    EXPECT_GT(stopped.time(), 0.0);
    EXPECT_LT(stopped.time(), 0.25);
    sim::StateWriter state;
    stopped.saveState(state);
    sim::Simulation resumed(scene.sim);
    const std::string bytes = state.take();
    sim::StateReader reader(bytes);
    resumed.restoreState(reader);
    resumed.advanceTo(0.25);
    EXPECT_EQ(resumed.particles().x, reference.particles().x);
    EXPECT_EQ(resumed.particles().vz, reference.particles().vz);
    // The incompressible solvers ask in their solves' iterations, and end the step there.
    if (solver == "wcsph") continue;
    sim::Simulation cut(scene.sim);
    int asked = 0;
    cut.setStopChecks({}, [&] { return ++asked >= 1; });
    EXPECT_EQ(stopAdvancing(cut, 0.25), "cut short");
    EXPECT_EQ(asked, 1);
    EXPECT_LE(cut.time(), double(scene.sim.timeStep.maxStep)) << "more than one step";
  }
}

// The surface stage's frame ends between its passes (field, crossings, narrow band).
TEST(HostileSignals, SurfacingAFrameStopsBetweenItsPasses) {
  const Scene scene = loadScene(kTinyScene);
  sim::Simulation simulation(scene.sim);
  const ParticleFrame frame = frameFromSimulation(scene, simulation, 0);
  int asked = 0;
  EXPECT_THROW(surfaceFrame(scene, frame, [&] { return ++asked >= 2; }), render::SurfacingStopped);
  EXPECT_EQ(asked, 2);
  EXPECT_FALSE(surfaceFrame(scene, frame, [] { return false; }).at("fluid").empty());
}

TEST(HostileSignals, SigtermInAFrameThatNeverEndsStopsTheSimulationWithinSeconds) {
  TempDir dir;
  const fs::path out = dir.path() / "out", log = dir.path() / "log.txt";
  // 1e9 steps to the end, 2.5e8 a frame: past the step limit, run anyway.
  const fs::path fixed = tinyWith(dir.path(), "fixed", {{"/time_step", {{"mode", "fixed"}, {"fixed_step", 1e-9}}}});
  const pid_t pid = test::startKurage({"sim", fixed.string(), "-o", out.string(), "--threads", "2", "--force"}, log);
  ASSERT_TRUE(waitForFile(out / "particles/0000.vdb", std::chrono::seconds(60))) << readText(log);
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  expectStoppedBySigterm(pid, log, out);
  EXPECT_FALSE(fs::exists(out / "particles/0001.vdb"));
  // The checkpoint holds the step the signal stopped frame 1 at.
  const Checkpoint c = readCheckpoint(out / "checkpoint.bin", stageHash(loadScene(fixed, {true}), "sim"));
  EXPECT_EQ(c.frame, 0);
  EXPECT_GT(c.time, 0.0);
  EXPECT_LT(c.time, 0.25);
}

// ---- 7. memory of every stage -----------------------------------------------------------------

TEST(HostileMemory, SurfacingAndRenderingMemoryIsEstimatedWhileLoading) {
  TempDir dir;
  const fs::path log = dir.path() / "log.txt", out = dir.path() / "out";
  const fs::path fine = tinyWith(dir.path(), "fine", {{"/surface/fluid/voxel_size", 0.001}});
  EXPECT_EQ(run({"check", fine.string()}, log), 2) << readText(log);
  EXPECT_TRUE(contains(readText(log), fine.string() + ": surface.fluid.voxel_size: surfacing a frame needs up to"))
      << readText(log);
  EXPECT_EQ(run({"run", fine.string(), "-o", out.string()}, log), 2) << readText(log);
  EXPECT_FALSE(fs::exists(out)) << "refused before anything is written";

  // The estimate bounds what the surface stage makes: the level set's memory at voxel 0.1 m.
  nlohmann::json doc = nlohmann::json::parse(readText(kTinyScene));
  doc.erase("$schema");
  doc["surface"]["fluid"]["voxel_size"] = 0.1;
  const Scene scene = parseScene(doc, "edited.json");
  const SceneEstimate e = estimateScene(scene);
  sim::Simulation simulation(scene.sim);
  simulation.advanceTo(0.5);
  size_t bytes = 0;
  for (const auto& [name, levelSet] : surfaceFrame(scene, frameFromSimulation(scene, simulation, 2)))
    bytes += levelSet.memoryBytes();
  EXPECT_GT(bytes, 0u);
  EXPECT_LT(double(bytes), e.surfaceBytes);
  EXPECT_EQ(e.renderBytes, 64.0 * 48.0 * kBytesPerPixel + e.surfaceBytes);
  // A resolution given on the command line is estimated too.
  if (double(::sysconf(_SC_PHYS_PAGES)) * double(::sysconf(_SC_PAGE_SIZE)) < 16384.0 * 16384.0 * kBytesPerPixel) {
    EXPECT_EQ(run({"render", kTinyScene.string(), "-o", out.string(), "--width", "16384", "--height", "16384"}, log), 2);
    EXPECT_TRUE(contains(readText(log), "render.width: rendering a frame needs up to")) << readText(log);
  }
}

// ---- 8. numbers on the command line -----------------------------------------------------------

TEST(HostileNumbers, CommandLineIntegersAreRangeCheckedNeverWrapped) {
  TempDir dir;
  const fs::path log = dir.path() / "log.txt", out = dir.path() / "out";
  for (const std::string frames : {"0-4294967299", "4294967298", "0-99999999999", "-1", "1-", "+3", "2-1", " 1", "1e3"}) {
    EXPECT_EQ(run({"sim", kTinyScene.string(), "-o", out.string(), "--frames", frames}, log), 2) << frames;
    EXPECT_TRUE(contains(readText(log), "--frames: ")) << readText(log);
    EXPECT_FALSE(contains(readText(log), "1215752191")) << readText(log);
  }
  for (const auto& [flag, value] : std::vector<std::pair<std::string, std::string>>{
           {"--threads", "4294967298"}, {"--checkpoint-every", "99999999999"}, {"--spp", "4294967297"}}) {
    EXPECT_EQ(run({"render", kTinyScene.string(), "-o", out.string(), flag, value}, log), 2) << flag;
    EXPECT_TRUE(contains(readText(log), flag + ": expected an integer in")) << readText(log);
  }
  EXPECT_EQ(run({"still", kTinyScene.string(), "--time", "nan", "-o", (dir.path() / "a.png").string()}, log), 2);
  EXPECT_TRUE(contains(readText(log), "--time: expected a finite number")) << readText(log);
  EXPECT_FALSE(fs::exists(out));
}

// ---- 10. export -------------------------------------------------------------------------------

TEST(HostileExport, ExportTakesTheRunLockRemovesStaleTemporariesAndStopsBetweenFrames) {
  TempDir dir;
  const fs::path out = dir.path() / "out", log = dir.path() / "log.txt";
  ASSERT_EQ(run({"sim", kTinyScene.string(), "-o", out.string(), "--threads", "2"}, log), 0) << readText(log);
  {
    const RunLock held(out, "test");
    EXPECT_EQ(run({"export", out.string(), "--format", "particles_ply"}, log), 1);
    EXPECT_TRUE(contains(readText(log), "pid " + std::to_string(::getpid()))) << readText(log);
  }
  // A temporary left by a killed export (a pid that no longer runs) goes with the next export.
  const pid_t dead = ::fork();
  if (dead == 0) ::_exit(0);
  ::waitpid(dead, nullptr, 0);
  fs::create_directories(out / "exports/particles");
  const fs::path stale = out / ("exports/particles/.0000.ply." + std::to_string(dead) + ".0.tmp");
  writeTextAtomic(stale, "half a file");
  ASSERT_EQ(run({"export", out.string(), "--format", "particles_ply"}, log), 0) << readText(log);
  EXPECT_FALSE(fs::exists(stale));
  EXPECT_TRUE(temporariesIn(out).empty());
  // Asked to stop, exportFrames finishes the frame it is on and makes no other.
  fs::remove_all(out / "exports");
  const Scene scene = loadScene(kTinyScene);
  int asked = 0;
  exportFrames(scene, parseExportFormats("particles_ply"), out, 0, 4, [&] { return ++asked > 2; });
  EXPECT_TRUE(fs::exists(out / "exports/particles/0001.ply"));
  EXPECT_FALSE(fs::exists(out / "exports/particles/0002.ply"));
}

// ---- 11. messages -----------------------------------------------------------------------------

TEST(HostileMessages, ErrorsNameTheFileAndTheKeyAndStayShort) {
  TempDir dir;
  const fs::path out = dir.path() / "out", log = dir.path() / "log.txt";
  // A run.json cut short: export names it.
  ASSERT_EQ(run({"sim", kTinyScene.string(), "-o", out.string(), "--threads", "2"}, log), 0) << readText(log);
  const std::string record = readText(out / "run.json");
  writeTextAtomic(out / "run.json", record.substr(0, record.size() / 2));
  EXPECT_EQ(run({"export", out.string(), "--format", "particles_ply"}, log), 1);
  EXPECT_TRUE(contains(readText(log), (out / "run.json").string() + ": not valid JSON")) << readText(log);
  // A 5 MB name is not echoed whole; nor is a 5 MB key.
  const fs::path named = tinyWith(dir.path(), "named", {{"/name", std::string(5 << 20, 'n')}});
  EXPECT_EQ(run({"check", named.string()}, log), 2);
  EXPECT_LT(readText(log).size(), 1000u);
  EXPECT_TRUE(contains(readText(log), "name: must be at most 200 bytes long")) << readText(log).substr(0, 300);
  const fs::path keyed = tinyWith(dir.path(), "keyed", {{"/" + std::string(5 << 20, 'k'), 1}});
  const auto start = Clock::now();
  EXPECT_EQ(run({"check", keyed.string()}, log), 2);
  EXPECT_LT(secondsSince(start), 20.0);
  EXPECT_LT(readText(log).size(), 1000u);
  EXPECT_TRUE(contains(readText(log), "unknown key")) << readText(log).substr(0, 300);
  // A voxel too fine for the positions names the key and the cache.
  nlohmann::json doc = nlohmann::json::parse(readText(kTinyScene));
  doc.erase("$schema");
  Scene scene = parseScene(doc, "edited.json");
  scene.surface.fluid.voxelSize = 1e-6f;
  ParticleFrame frame;
  frame.px = {15.0f};
  frame.py = {4.0f};
  frame.pz = {9.0f};
  frame.vx = frame.vy = frame.vz = {0.0f};
  frame.id = {0};
  frame.kind = {0};
  try {
    surfaceFrame(scene, frame);
    ADD_FAILURE() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_TRUE(contains(e.what(), "surface.fluid.voxel_size = 1e-06 m: ")) << e.what();
  }
}

}  // namespace
}  // namespace kurage::pipeline
