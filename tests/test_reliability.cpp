// Runs that survive (issue 16; docs/design/reliability.md lists which test proves which promise):
//  - the I/O layer: unique exclusive temporaries, checked writes, nothing truncated under a
//    final name when the disk is "full" (a file-size limit, RLIMIT_FSIZE with SIGXFSZ ignored)
//    at every stage (sim, surface, render, video);
//  - files that cannot lie: truncated, flipped, foreign-scene and wrong-type particle caches and
//    surface files are errors naming the file, never a crash or wrong data.
#include "pipeline/io/files.h"
#include "pipeline/io/image_file.h"
#include "pipeline/io/run_lock.h"
#include "pipeline/io/stamp.h"
#include "pipeline/io/surface_file.h"
#include "pipeline/io/video.h"
#include "pipeline/io/particle_cache.h"
#include "pipeline/scene.h"
#include "pipeline/stages.h"
#include "test_util.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <thread>

#include <csignal>
#include <fcntl.h>
#include <fstream>
#include <random>
#include <set>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

namespace kurage::pipeline {
namespace {

namespace fs = std::filesystem;
using kurage::test::expectErrorNamingPath;
using kurage::test::TempDir;
using kurage::test::temporariesIn;

const fs::path kTinyScene = test::sourceDir() / "tests/scenes/tiny_dam_break.json";

// Runs `body` in a forked child under a file-size limit of `bytes` with SIGXFSZ ignored (so a
// write past the limit fails with EFBIG, as on a full disk); returns the child's exit code.
template <typename Body>
int inChildWithFileSizeLimit(rlim_t bytes, Body body) {
  const pid_t pid = ::fork();
  if (pid == 0) {
    std::signal(SIGXFSZ, SIG_IGN);
    const rlimit limit{bytes, bytes};
    if (::setrlimit(RLIMIT_FSIZE, &limit) != 0) ::_exit(90);
    int code = 91;
    try {
      code = body();
    } catch (...) {
      code = 92;
    }
    ::_exit(code);
  }
  int status = 0;
  ::waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// build/kurage under a file-size limit (KiB), SIGXFSZ ignored by the shell (or left to kurage,
// which ignores it itself: `trapped` false, a plain `ulimit -f`); output into `log`.
int runKurageLimited(const std::string& arguments, int kib, const fs::path& log, bool trapped = true) {
  const std::string command = "bash -c \"ulimit -f " + std::to_string(kib) + "; " + (trapped ? "trap '' XFSZ; " : "") + "exec " +
                              (test::binaryDir() / "kurage").string() + " " + arguments + "\" > " + log.string() +
                              " 2>&1";
  const int status = std::system(command.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

ParticleFrame smallFrame(size_t n, unsigned seed, int number = 3) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-2.0f, 2.0f);
  ParticleFrame f;
  f.time = 0.125 * number;
  f.frame = number;
  f.sceneHash = "00000000000000aa";
  for (size_t i = 0; i < n; ++i) {
    f.px.push_back(u(rng)); f.py.push_back(u(rng)); f.pz.push_back(u(rng));
    f.vx.push_back(u(rng)); f.vy.push_back(u(rng)); f.vz.push_back(u(rng));
    f.id.push_back(int64_t(i));
    f.kind.push_back(0);
  }
  return f;
}

// ---- the I/O layer ----------------------------------------------------------------------------

TEST(AtomicFile, TemporariesAreUniqueHiddenAndRemovedOnFailure) {
  TempDir dir;
  const fs::path target = dir.path() / "a.txt";
  std::set<fs::path> names;
  {
    TempFile one(target), two(target);
    names = {one.path(), two.path()};
    EXPECT_EQ(names.size(), 2u);
    for (const fs::path& p : names) {
      EXPECT_TRUE(fs::exists(p));
      EXPECT_EQ(p.filename().string()[0], '.');
      EXPECT_NE(p.filename().string().find(std::to_string(::getpid())), std::string::npos) << p;
    }
  }  // neither committed: both removed
  for (const fs::path& p : names) EXPECT_FALSE(fs::exists(p)) << p;
  EXPECT_FALSE(fs::exists(target));
  writeFileAtomic(target, "hello");
  EXPECT_EQ(readFile(target), "hello");
  writeFileAtomic(target, "again");  // replaces
  EXPECT_EQ(readFile(target), "again");
  expectErrorNamingPath([&] { writeFileAtomic(dir.path() / "no/such/folder/x", "x"); }, dir.path() / "no/such/folder/x");
  expectErrorNamingPath([&] { readFile(dir.path() / "missing"); }, dir.path() / "missing", "No such file");
  EXPECT_TRUE(temporariesIn(dir.path()).empty());
}

TEST(AtomicFile, FullDiskLeavesTheOldFileAndNoTemporary) {
  TempDir dir;
  const fs::path target = dir.path() / "big.bin";
  writeFileAtomic(target, "old contents");
  const int code = inChildWithFileSizeLimit(4096, [&] {
    try {
      writeFileAtomic(target, std::string(100000, 'x'));
    } catch (const IoError& e) {
      const std::string what = e.what();
      return what.find(target.string()) != std::string::npos && what.find("File too large") != std::string::npos ? 0 : 3;
    }
    return 4;  // no error: the failure went unnoticed
  });
  EXPECT_EQ(code, 0);
  EXPECT_EQ(readFile(target), "old contents");
  EXPECT_TRUE(temporariesIn(dir.path()).empty());
}

// Every stage under a file-size limit: exit 1, an error naming the file, and every file under
// its final name complete (it reads back), no temporary left.
void expectCleanFailure(int code, const fs::path& log, const std::string& file, const fs::path& out) {
  const std::string text = readText(log);
  EXPECT_EQ(code, 1) << text;
  EXPECT_NE(text.find(file), std::string::npos) << text;
  EXPECT_NE(text.find("File too large"), std::string::npos) << text;
  EXPECT_TRUE(temporariesIn(out).empty());
  for (const char* folder : {"particles", "surfaces"})
    if (fs::exists(out / folder))
      for (const auto& entry : fs::directory_iterator(out / folder)) {
        if (std::string(folder) == "particles") EXPECT_NO_THROW(readParticleFrame(entry.path())) << entry.path();
        else EXPECT_NO_THROW(readSurfaceFile(entry.path())) << entry.path();
      }
  if (fs::exists(out / "frames")) {
    for (const auto& entry : fs::directory_iterator(out / "frames")) EXPECT_NO_THROW(render::readPng(entry.path()));
  }
}

TEST(FullDisk, EveryStageFailsCleanly) {
  TempDir dir;
  const fs::path out = dir.path() / "out";
  const fs::path log = dir.path() / "log.txt";
  const std::string scene = kTinyScene.string() + " -o " + out.string() + " --threads 2 ";
  // sim: the caches are ~11 KB each (run.json, written first, ~8 KB).
  expectCleanFailure(runKurageLimited("sim " + scene, 10, log), log, "particles/0000.vdb", out);
  EXPECT_FALSE(fs::exists(out / "particles/0000.vdb"));
  ASSERT_EQ(test::runKurage("sim " + scene, log), 0) << readText(log);
  // surface: ~170 KB each.
  expectCleanFailure(runKurageLimited("surface " + scene, 64, log), log, "surfaces/0000.vdb", out);
  ASSERT_EQ(test::runKurage("surface " + scene, log), 0) << readText(log);
  // render: frames of 256 x 192 are over 16 KB (run.json, written first, is ~10 KB).
  expectCleanFailure(runKurageLimited("render --no-video --width 256 --height 192 --spp 1 " + scene, 16, log), log,
                     "frames/0000.png", out);
  EXPECT_FALSE(fs::exists(out / "frames/0000.png"));
}

// A plain `ulimit -f` leaves SIGXFSZ at its default action, which ends a process mid-write
// without a word (exit 153): kurage ignores it, so the checked write reports the full disk.
TEST(FullDisk, AFileSizeLimitWithTheSignalLeftAloneFailsCleanlyToo) {
  TempDir dir;
  const fs::path out = dir.path() / "out";
  const fs::path log = dir.path() / "log.txt";
  const std::string scene = kTinyScene.string() + " -o " + out.string() + " --threads 2 ";
  expectCleanFailure(runKurageLimited("sim " + scene, 10, log, false), log, "particles/0000.vdb", out);
  EXPECT_EQ(nlohmann::json::parse(readText(out / "run.json"))["status"], "failed");
  ASSERT_EQ(test::runKurage("sim " + scene, log), 0) << readText(log);
  expectCleanFailure(runKurageLimited("surface " + scene, 64, log, false), log, "surfaces/0000.vdb", out);
  EXPECT_EQ(nlohmann::json::parse(readText(out / "run.json"))["status"], "failed");
  ASSERT_EQ(test::runKurage("surface " + scene, log), 0) << readText(log);
  // export (no run.json of its own): a PLY of the particles is ~9 KB.
  expectCleanFailure(runKurageLimited("export " + out.string() + " --format particles_ply", 4, log, false), log,
                     "exports/particles/0000.ply", out);
}

TEST(FullDisk, VideoFailureIsAnErrorAndLeavesNoMovie) {
  if (!onPath("ffmpeg")) GTEST_SKIP() << "ffmpeg is not on the PATH";
  TempDir dir;
  const fs::path frames = dir.path() / "frames";
  fs::create_directories(frames);
  for (int f = 0; f < 5; ++f) {
    render::Image image(64, 48, Eigen::Vector4f(0.1f * float(f), 0.5f, 0.2f, 1.0f));
    writePng(image, frameFile(frames, f, "png"));
  }
  const fs::path movie = dir.path() / "movie.mp4";
  const int code = inChildWithFileSizeLimit(1024, [&] {
    try {
      encodeVideo(frames, 0, 5, 4.0, movie);
    } catch (const IoError& e) {
      return std::string(e.what()).find(movie.string()) != std::string::npos ? 0 : 3;
    }
    return 4;
  });
  EXPECT_EQ(code, 0);
  EXPECT_FALSE(fs::exists(movie));
  EXPECT_TRUE(temporariesIn(dir.path()).empty());
  // Without the limit the movie is made and checked (ffprobe counts 5 frames).
  EXPECT_TRUE(encodeVideo(frames, 0, 5, 4.0, movie).encoded);
  EXPECT_GT(fs::file_size(movie), 0u);
}

TEST(Video, FramesRenderedAgainRemakeTheMovie) {
  // The movie's stamp names the frames' bytes as well as the render settings: frames rendered
  // again with the same settings but other pixels (deleted and redone by another build of the
  // tracer) must not leave the old movie standing as "up to date".
  if (!onPath("ffmpeg")) GTEST_SKIP() << "ffmpeg is not on the PATH";
  TempDir dir;
  const Scene scene = loadScene(kTinyScene);
  const fs::path frames = dir.path() / "frames";
  fs::create_directories(frames);
  const auto writeFrames = [&](float red) {
    for (int f = 0; f < 3; ++f)
      writePng(render::Image(64, 48, Eigen::Vector4f(red, 0.1f * float(f), 0.2f, 1.0f)), frameFile(frames, f, "png"));
  };
  writeFrames(0.2f);
  const fs::path movie = dir.path() / (scene.name + ".mp4");
  encodeSceneVideo(scene, dir.path(), 0, 2);
  ASSERT_TRUE(fs::exists(movie));
  const auto made = fs::last_write_time(movie);
  std::this_thread::sleep_for(std::chrono::milliseconds(20));
  encodeSceneVideo(scene, dir.path(), 0, 2);  // the same frames: kept
  EXPECT_EQ(fs::last_write_time(movie), made);
  writeFrames(0.8f);
  encodeSceneVideo(scene, dir.path(), 0, 2);  // other pixels, the same settings: made again
  EXPECT_NE(fs::last_write_time(movie), made);
}

TEST(FullDisk, FfmpegErrorWithExitZeroIsCaught) {
  // ffmpeg on a full disk prints "Error writing trailer" and exits 0; a stand-in does just that.
  TempDir dir;
  const fs::path bin = dir.path() / "bin";
  fs::create_directories(bin);
  {
    std::ofstream script(bin / "ffmpeg");
    script << "#!/bin/sh\nfor last; do :; done\nprintf 'partial' > \"$last\"\n"
              "echo '[out#0/mp4] Error writing trailer: No space left on device' >&2\nexit 0\n";
  }
  fs::permissions(bin / "ffmpeg", fs::perms::owner_all);
  const fs::path movie = dir.path() / "movie.mp4";
  const int code = inChildWithFileSizeLimit(RLIM_INFINITY, [&] {
    ::setenv("PATH", (bin.string() + ":" + std::getenv("PATH")).c_str(), 1);
    try {
      encodeVideo(dir.path(), 0, 5, 4.0, movie);
    } catch (const IoError& e) {
      return std::string(e.what()).find("Error writing trailer") != std::string::npos ? 0 : 3;
    }
    return 4;
  });
  EXPECT_EQ(code, 0);
  EXPECT_FALSE(fs::exists(movie));
  EXPECT_TRUE(temporariesIn(dir.path()).empty());
}

// ---- files that cannot lie --------------------------------------------------------------------

// Every damage of a good file: cuts (the last 10 bytes, halves, 1 byte), single flipped bytes at
// spread positions, 64 flipped bytes at random: each must be an error naming the file.
template <typename Read>
void expectEveryDamageCaught(const fs::path& good, const fs::path& folder, Read read) {
  const std::string bytes = readFile(good);
  const fs::path bad = folder / "damaged.vdb";
  const auto check = [&](const std::string& damaged, const std::string& what) {
    std::ofstream(bad, std::ios::binary | std::ios::trunc) << damaged;
    SCOPED_TRACE(what);
    expectErrorNamingPath([&] { read(bad); }, bad);
  };
  for (const size_t keep : {bytes.size() - 10, bytes.size() - 1, bytes.size() / 2, size_t(100), size_t(8), size_t(0)})
    check(bytes.substr(0, keep), "cut to " + std::to_string(keep) + " bytes");
  for (size_t at = 0; at < bytes.size(); at += std::max<size_t>(1, bytes.size() / 97)) {
    std::string damaged = bytes;
    damaged[at] = char(damaged[at] ^ 0x5a);
    check(damaged, "byte " + std::to_string(at) + " flipped");
  }
  std::mt19937 rng(7);
  for (int trial = 0; trial < 10; ++trial) {
    std::string damaged = bytes;
    const size_t start = std::uniform_int_distribution<size_t>(0, bytes.size() - 64)(rng);
    for (size_t i = start; i < start + 64; ++i) damaged[i] = char(rng());
    check(damaged, "64 bytes flipped at " + std::to_string(start));
  }
}

TEST(FilesCannotLie, DamagedParticleCachesAreErrorsNamingTheFile) {
  TempDir dir;
  const fs::path good = dir.path() / "0003.vdb";
  writeParticleFrame(good, smallFrame(500, 1));
  EXPECT_EQ(readParticleFrame(good).size(), 500u);
  expectEveryDamageCaught(good, dir.path(), [](const fs::path& p) { readParticleFrame(p); });
}

TEST(FilesCannotLie, DamagedSurfaceFilesAreErrorsNamingTheFile) {
  TempDir dir;
  const fs::path good = dir.path() / "0003.vdb";
  const render::LevelSet blob = render::buildMetaballLevelSet({Eigen::Vector3f::Zero(), Eigen::Vector3f(1, 0, 0)},
                                                              render::MetaballParams{});
  writeSurfaceFile(good, {{"fluid", &blob}}, 0.5, 3, "00000000000000aa");
  EXPECT_EQ(readSurfaceFile(good).size(), 1u);
  expectEveryDamageCaught(good, dir.path(), [](const fs::path& p) { readSurfaceFile(p); });
}

TEST(FilesCannotLie, ForeignWrongTypeAndWrongFrameFilesAreRefused) {
  TempDir dir;
  const fs::path cache = dir.path() / "cache.vdb";
  const fs::path surface = dir.path() / "surface.vdb";
  writeParticleFrame(cache, smallFrame(50, 2, 3));
  const render::LevelSet blob = render::buildMetaballLevelSet({Eigen::Vector3f::Zero()}, render::MetaballParams{});
  writeSurfaceFile(surface, {{"fluid", &blob}}, 0.5, 3, "00000000000000aa");
  // Another scene's file.
  expectErrorNamingPath([&] { readParticleFrame(cache, {"sim", "00000000000000bb", 3}); }, cache, "other scene parameters");
  expectErrorNamingPath([&] { readSurfaceFile(surface, {"surface", "00000000000000bb", 3}); }, surface,
                        "other scene parameters");
  // Another frame's file.
  expectErrorNamingPath([&] { readParticleFrame(cache, {"sim", "00000000000000aa", 4}); }, cache, "holds frame 3");
  expectErrorNamingPath([&] { readSurfaceFile(surface, {"surface", "00000000000000aa", 4}); }, surface, "holds frame 3");
  // The wrong kind of file.
  expectErrorNamingPath([&] { readParticleFrame(surface); }, surface, "wrong kind of file");
  expectErrorNamingPath([&] { readSurfaceFile(cache); }, cache, "wrong kind of file");
  // An OpenVDB file kurage did not stamp (another program's, or an older kurage's).
  const fs::path plain = dir.path() / "plain.vdb";
  {
    std::ofstream out(plain, std::ios::binary);
    render::writeLevelSets(out, {{"fluid", &blob}}, render::LevelSetFileInfo{});
  }
  expectErrorNamingPath([&] { readSurfaceFile(plain); }, plain, "not a kurage file");
  expectErrorNamingPath([&] { readParticleFrame(plain); }, plain, "not a kurage file");
  // The right expectations pass.
  EXPECT_EQ(readParticleFrame(cache, {"sim", "00000000000000aa", 3}).sceneHash, "00000000000000aa");
  EXPECT_EQ(readSurfaceFile(surface, {"surface", "00000000000000aa", 3}).size(), 1u);
}

TEST(FilesCannotLie, StagesRefuseAnotherScenesFiles) {
  TempDir dir;
  const fs::path out = dir.path() / "out";
  const fs::path log = dir.path() / "log.txt";
  ASSERT_EQ(test::runKurage("sim " + kTinyScene.string() + " -o " + out.string(), log), 0) << readText(log);
  // The same scene with another gravity: its surface stage must not take these caches.
  std::string text = readText(kTinyScene);
  const std::string gravity = "\"gravity\": [0, 0, -6.0]";
  ASSERT_NE(text.find(gravity), std::string::npos);
  text.replace(text.find(gravity), gravity.size(), "\"gravity\": [0, 0, -9.0]");
  text.replace(text.find("../../scenes/schema.json"), 24, "schema.json");
  const fs::path other = dir.path() / "other.json";
  writeTextAtomic(other, text);
  EXPECT_EQ(test::runKurage("surface " + other.string() + " -o " + out.string(), log), 1) << readText(log);
  EXPECT_NE(readText(log).find("particles/0000.vdb: made from other scene parameters"), std::string::npos)
      << readText(log);
  // A render setting does not invalidate the caches or the surfaces.
  ASSERT_EQ(test::runKurage("surface " + kTinyScene.string() + " -o " + out.string() + " --frames 0-1", log), 0)
      << readText(log);
  EXPECT_EQ(test::runKurage("render " + kTinyScene.string() + " -o " + out.string() +
                                " --frames 0-1 --no-video --width 16 --height 12 --spp 1",
                            log),
            0)
      << readText(log);
}

// ---- one run per OUT, clean interruption ------------------------------------------------------

TEST(RunLock, ASecondRunIntoTheSameFolderIsRefusedNamingTheHolder) {
  TempDir dir;
  const fs::path out = dir.path() / "out";
  const fs::path log = dir.path() / "log.txt";
  {
    const RunLock held(out, "test");
    EXPECT_THROW(RunLock(out, "again"), IoError);  // even within one process (a new open file)
    EXPECT_EQ(test::runKurage("sim " + kTinyScene.string() + " -o " + out.string(), log), 1) << readText(log);
    const std::string text = readText(log);
    EXPECT_NE(text.find("another kurage run"), std::string::npos) << text;
    EXPECT_NE(text.find("pid " + std::to_string(::getpid())), std::string::npos) << text;
    EXPECT_FALSE(fs::exists(out / "particles")) << "the refused run wrote nothing";
  }
  // Released with its holder: the run goes ahead.
  EXPECT_EQ(test::runKurage("sim " + kTinyScene.string() + " -o " + out.string(), log), 0) << readText(log);
}

TEST(Interrupt, SigintStopsTheRunAndRunJsonSaysInterrupted) {
  TempDir dir;
  const fs::path out = dir.path() / "out";
  const fs::path log = dir.path() / "log.txt";
  const pid_t pid = test::startKurage({"run", kTinyScene.string(), "-o", out.string(), "--threads", "2", "--width",
                                       "320", "--height", "240", "--spp", "64", "--no-video"},
                                      log);
  // Wait for the first frame, then interrupt: the remaining four take seconds.
  const auto start = std::chrono::steady_clock::now();
  while (!fs::exists(out / "frames/0000.png") && std::chrono::steady_clock::now() - start < std::chrono::seconds(60))
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  ::kill(pid, SIGINT);
  int status = 0;
  ::waitpid(pid, &status, 0);
  const std::string text = readText(log);
  ASSERT_TRUE(WIFEXITED(status)) << text;
  EXPECT_EQ(WEXITSTATUS(status), 128 + SIGINT) << text;
  EXPECT_NE(text.find("interrupted by SIGINT"), std::string::npos) << text;
  const nlohmann::json run = nlohmann::json::parse(readText(out / "run.json"));
  EXPECT_EQ(run["status"], "interrupted");
  EXPECT_FALSE(fs::exists(out / "frames/0004.png"));
  EXPECT_TRUE(temporariesIn(out).empty());
  // A complete run says so.
  ASSERT_EQ(test::runKurage("sim " + kTinyScene.string() + " -o " + out.string(), log), 0) << readText(log);
  EXPECT_EQ(nlohmann::json::parse(readText(out / "run.json"))["status"], "complete");
}

// ---- inputs checked before anything is allocated ---------------------------------------------

// The tiny scene with one edit (a line of Python-free JSON surgery: key path -> value).
nlohmann::json tinyWith(const std::string& pointer, const nlohmann::json& value) {
  nlohmann::json doc = nlohmann::json::parse(readText(kTinyScene));
  doc.erase("$schema");
  doc[nlohmann::json::json_pointer(pointer)] = value;
  return doc;
}

void expectSceneError(const nlohmann::json& doc, const std::string& jsonPath, const std::string& detail,
                      const LoadOptions& options = {}) {
  try {
    parseScene(doc, "edited.json", options);
    ADD_FAILURE() << "accepted: " << jsonPath << " " << detail;
  } catch (const SceneError& e) {
    EXPECT_EQ(e.jsonPath(), jsonPath) << e.what();
    EXPECT_NE(std::string(e.what()).find(detail), std::string::npos) << e.what();
  }
}

TEST(SceneLimits, AbsurdScenesAreRefusedWithTheEstimate) {
  // Numbers a 32-bit float cannot hold.
  expectSceneError(tinyWith("/fluid/spacing", 1e-300), "fluid.spacing", "too small for a 32-bit float");
  expectSceneError(tinyWith("/container/max", {1e308, 5, 10}), "container.max[0]", "beyond the range of a 32-bit float");
  // A finite but absurd container: the neighbour grid would need 1.9e31 cells (hard limit).
  expectSceneError(tinyWith("/container/max", {1e30, 5, 10}), "container", "cells");
  expectSceneError(tinyWith("/container/max", {1e30, 5, 10}), "container", "cells", {true});
  // A duration that overflows the frame count (hard), and one above the soft limit.
  expectSceneError(tinyWith("/output/duration", 1e9), "output.duration", "4e+09 frames");
  expectSceneError(tinyWith("/output/duration", 1e9), "output.duration", "4e+09 frames", {true});
  expectSceneError(tinyWith("/output/duration", 1e5), "output.duration", "--force");
  EXPECT_EQ(parseScene(tinyWith("/output/duration", 1e5), "edited.json", {true}).output.frameCount(), 400001);
  // 2e8 particles: refused before anything is allocated, with the estimate; --force lifts it.
  nlohmann::json fine = tinyWith("/fluid/spacing", 0.01);
  expectSceneError(fine, "fluid_blocks", "2e+08 particles");
  EXPECT_NEAR(estimateScene(parseScene(fine, "edited.json", {true})).particles, 5.0 / 0.01 * 500 * 800, 2e6);
  // A fine body with a wide connection radius: ~3e7 springs, refused before the bodies are built
  // (building them took 2 minutes and several GB; found by the study fuzzer, tests/fuzz/README.md).
  nlohmann::json body = tinyWith("/bodies", nlohmann::json::parse(
      R"([{"name": "box", "shape": "box", "min": [6, 1, 1], "max": [9, 4, 4], "spacing": 0.15, "connection_radius": 2.4}])"));
  expectSceneError(body, "bodies[0].spacing", "springs");
  nlohmann::json coarse = body;
  coarse["bodies"][0]["spacing"] = 0.5;
  const SceneEstimate estimate = estimateScene(parseScene(coarse, "edited.json"));
  EXPECT_EQ(estimate.bodyParticles, 7.0 * 7.0 * 7.0);  // 3 m at 0.5 m: 7 a side
  EXPECT_EQ(estimate.springs, 343.0 * 343.0 / 2.0);    // every pair within 2.4 m at most
  // The tiny scene itself is well within.
  const SceneEstimate tiny = estimateScene(loadScene(kTinyScene));
  EXPECT_EQ(tiny.particles, 200.0);
  EXPECT_EQ(tiny.frames, 5.0);
}

TEST(SceneLimits, NameMustBeAPlainFileName) {
  for (const std::string& name : std::vector<std::string>{"../../escape", "/tmp/abs", "a/b", std::string("a\0b", 3), "..", ".", "", "a\nb"})
    expectSceneError(tinyWith("/name", name), "name", "must", {});
  EXPECT_EQ(parseScene(tinyWith("/name", "my scene-2 (final)"), "edited.json").name, "my scene-2 (final)");
}

TEST(SceneLimits, DuplicateKeysAndHugeNumbersAreSceneErrors) {
  TempDir dir;
  const auto load = [&](const std::string& text) {
    const fs::path file = dir.path() / "scene.json";
    writeTextAtomic(file, text);
    return loadScene(file);
  };
  const auto expectError = [&](const std::string& text, const std::string& jsonPath, const std::string& detail) {
    try {
      load(text);
      ADD_FAILURE() << "accepted " << text;
    } catch (const SceneError& e) {
      EXPECT_EQ(e.jsonPath(), jsonPath) << e.what();
      EXPECT_NE(std::string(e.what()).find(detail), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find((dir.path() / "scene.json").string()), std::string::npos) << e.what();
    }
  };
  expectError(R"({"name": "a", "name": "b"})", "name", "duplicate key");
  expectError(R"({"fluid": {"spacing": 1, "spacing": 2}})", "fluid.spacing", "duplicate key");
  expectError(R"({"bodies": [{"name": "a"}, {"name": "b", "name": "c"}]})", "bodies[].name", "duplicate key");
  expectError(R"({"fluid": {"spacing": 1e400}})", "", "1e400");
  // The same key in sibling objects is no duplicate (min and max in container and fluid_blocks[0]).
  EXPECT_NO_THROW(load(readText(kTinyScene)));
}

TEST(SceneLimits, SceneAndCommandLineErrorsExitTwo) {
  TempDir dir;
  const fs::path log = dir.path() / "log.txt";
  const fs::path out = dir.path() / "out";
  const auto write = [&](const nlohmann::json& doc) {
    const fs::path file = dir.path() / "scene.json";
    writeTextAtomic(file, doc.dump());
    return file.string();
  };
  EXPECT_EQ(test::runKurage("check " + write(tinyWith("/fluid/spacing", 1e-300)), log), 2) << readText(log);
  EXPECT_EQ(test::runKurage("sim " + write(tinyWith("/name", "../../escape")) + " -o " + out.string(), log), 2);
  EXPECT_NE(readText(log).find("name: must be a plain file name"), std::string::npos) << readText(log);
  EXPECT_EQ(test::runKurage("sim " + kTinyScene.string() + " -o " + out.string() + " --frames 0-99", log), 2)
      << readText(log);
  EXPECT_NE(readText(log).find("the scene has frames 0-4"), std::string::npos) << readText(log);
  writeTextAtomic(dir.path() / "huge.json", R"({"fluid": {"spacing": 1e400}})");
  EXPECT_EQ(test::runKurage("check " + (dir.path() / "huge.json").string(), log), 2) << readText(log);
  EXPECT_NE(readText(log).find((dir.path() / "huge.json").string()), std::string::npos) << readText(log);
  EXPECT_FALSE(fs::exists(out)) << "nothing written for a refused scene";
}

}  // namespace
}  // namespace kurage::pipeline
