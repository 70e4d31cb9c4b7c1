// kurage farm against a real Slurm (label cluster): a private single-node cluster started by the
// CTest fixture slurm_start (tests/slurm_local.sh, root needed) and stopped by slurm_stop.
// The farmed frames are byte-identical to `kurage run`'s and the caches hold the same contents; a
// failed task cancels the merge, `kurage farm status` names the missing frames, and resubmitting
// runs only the failed chunk.
#include "pipeline/io/files.h"
#include "pipeline/particle_cache.h"

#include "test_util.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <thread>

namespace kurage {
namespace {

namespace fs = std::filesystem;
using pipeline::readText;

const fs::path kScene = test::sourceDir() / "tests/scenes/tiny_dam_break.json";  // frames 0-4

std::string run(const std::string& command) {
  std::string out;
  FILE* pipe = popen((command + " 2>&1").c_str(), "r");
  char buffer[4096];
  size_t n;
  while ((n = fread(buffer, 1, sizeof buffer, pipe)) > 0) out.append(buffer, n);
  pclose(pipe);
  return out;
}

// Waits until none of the farm's jobs is pending or running (squeue; no accounting database).
void waitForFarm(const fs::path& out) {
  const nlohmann::json jobs = nlohmann::json::parse(readText(out / "farm/jobs.json"));
  std::string ids;
  for (const auto& [stage, id] : jobs.items())
    if (id.is_string()) {
      if (!ids.empty()) ids += ',';
      ids += id.get<std::string>();
    }
  const auto start = std::chrono::steady_clock::now();
  while (!run("squeue -h -j " + ids + " -t PD,R,CG,CF").empty()) {
    ASSERT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(180)) << "jobs " << ids << " still queued";
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
  }
}

void expectSameFrames(const fs::path& a, const fs::path& b, int first, int last) {
  for (int f = first; f <= last; ++f) {
    EXPECT_EQ(readText(pipeline::frameFile(a / "frames", f, "png")), readText(pipeline::frameFile(b / "frames", f, "png")))
        << "frame " << f;
    // OpenVDB writes a random UUID into each header: compare the caches' contents.
    const pipeline::ParticleFrame x = pipeline::readParticleFrame(pipeline::frameFile(a / "particles", f, "vdb"));
    const pipeline::ParticleFrame y = pipeline::readParticleFrame(pipeline::frameFile(b / "particles", f, "vdb"));
    EXPECT_TRUE(x.px == y.px && x.py == y.py && x.pz == y.pz && x.vx == y.vx && x.id == y.id && x.kind == y.kind &&
                x.time == y.time)
        << "cache " << f;
  }
}

class Farm : public ::testing::Test {
protected:
  void SetUp() override {
    if (!std::getenv("SLURM_CONF")) GTEST_SKIP() << "no Slurm: run through ctest (fixture slurm_start)";
    local_ = dir_.path() / "local";
    ASSERT_EQ(test::runKurage("run " + kScene.string() + " -o " + local_.string() + " --no-video", dir_.path() / "l.txt"), 0);
  }
  test::TempDir dir_;
  fs::path local_;
};

TEST_F(Farm, ThreeTasksGiveTheFramesOfALocalRun) {
  const fs::path out = dir_.path() / "farmed";
  ASSERT_EQ(test::runKurage("farm " + kScene.string() + " -o " + out.string() + " --frames-per-task 2 --submit",
                            dir_.path() / "farm.txt"),
            0)
      << readText(dir_.path() / "farm.txt");
  EXPECT_NE(readText(out / "farm/frames.sbatch").find("chunks=(0-1 2-3 4-4)"), std::string::npos);
  waitForFarm(out);
  expectSameFrames(local_, out, 0, 4);
  const nlohmann::json record = nlohmann::json::parse(readText(out / "run.json"));
  EXPECT_EQ(record["stages"]["render"]["tasks"].size(), 3u);
  EXPECT_GT(record["stages"]["sim"]["seconds"].get<double>(), 0.0);
  EXPECT_TRUE(fs::exists(out / "tiny_dam_break.mp4"));
  const std::string status = run((test::binaryDir() / "kurage").string() + " farm status " + out.string());
  EXPECT_NE(status.find("merge  job"), std::string::npos) << status;
  EXPECT_NE(status.find("COMPLETED"), std::string::npos) << status;
  EXPECT_NE(status.find("missing frames: none"), std::string::npos) << status;
}

TEST_F(Farm, AFailedTaskCancelsTheMergeAndAResubmitRunsOnlyWhatIsMissing) {
  const fs::path out = dir_.path() / "farmed";
  // The caches exist (so the farm submits no simulation), but frame 3's is damaged.
  ASSERT_EQ(test::runKurage("sim " + kScene.string() + " -o " + out.string(), dir_.path() / "sim.txt"), 0);
  const fs::path damaged = pipeline::frameFile(out / "particles", 3, "vdb");
  pipeline::writeTextAtomic(damaged, "not an OpenVDB file");
  ASSERT_EQ(test::runKurage("farm " + kScene.string() + " -o " + out.string() + " --frames-per-task 2 --submit",
                            dir_.path() / "farm1.txt"),
            0)
      << readText(dir_.path() / "farm1.txt");
  nlohmann::json jobs = nlohmann::json::parse(readText(out / "farm/jobs.json"));
  EXPECT_FALSE(jobs.contains("sim"));
  waitForFarm(out);
  const std::string status = run((test::binaryDir() / "kurage").string() + " farm status " + out.string());
  EXPECT_NE(status.find("FAILED"), std::string::npos) << status;
  EXPECT_NE(status.find("merge  job " + jobs["merge"].get<std::string>() + ": 1 CANCELLED"), std::string::npos) << status;
  EXPECT_NE(status.find("missing frames: 2-3 (tasks 1)"), std::string::npos) << status;
  EXPECT_FALSE(fs::exists(out / "run.json") && nlohmann::json::parse(readText(out / "run.json")).contains("farm"));

  // Mended, and submitted again: only chunk 1 runs, then the merge.
  fs::copy_file(pipeline::frameFile(local_ / "particles", 3, "vdb"), damaged, fs::copy_options::overwrite_existing);
  const auto before = fs::last_write_time(pipeline::frameFile(out / "frames", 0, "png"));
  ASSERT_EQ(test::runKurage("farm " + kScene.string() + " -o " + out.string() + " --frames-per-task 2 --submit",
                            dir_.path() / "farm2.txt"),
            0)
      << readText(dir_.path() / "farm2.txt");
  jobs = nlohmann::json::parse(readText(out / "farm/jobs.json"));
  EXPECT_FALSE(jobs.contains("sim"));
  EXPECT_EQ(jobs["frame_tasks"], nlohmann::json::array({1}));
  waitForFarm(out);
  EXPECT_EQ(fs::last_write_time(pipeline::frameFile(out / "frames", 0, "png")), before) << "frame 0 was redone";
  expectSameFrames(local_, out, 0, 4);
  EXPECT_NE(run((test::binaryDir() / "kurage").string() + " farm status " + out.string()).find("missing frames: none"),
            std::string::npos);
}

TEST(FarmCommand, BadInputIsRefused) {
  test::TempDir dir;
  // A relative OUT cannot be submitted: the nodes would not find it.
  EXPECT_EQ(test::runKurage("farm " + kScene.string() + " -o relative/out --submit", dir.path() / "a.txt"), 2);
  EXPECT_NE(readText(dir.path() / "a.txt").find("absolute"), std::string::npos);
  // No sbatch on the PATH: a clear error with sbatch's message, the scripts left for inspection.
  const fs::path out = dir.path() / "out";
  const std::string command = "PATH=/nonexistent " + (test::binaryDir() / "kurage").string() + " farm " +
                              kScene.string() + " -o " + out.string() + " --submit > " +
                              (dir.path() / "b.txt").string() + " 2>&1";
  const int status = std::system(command.c_str());
  EXPECT_EQ(WEXITSTATUS(status), 1);
  EXPECT_NE(readText(dir.path() / "b.txt").find("sbatch"), std::string::npos) << readText(dir.path() / "b.txt");
  EXPECT_TRUE(fs::exists(out / "farm/sim.sbatch"));
  EXPECT_EQ(test::runKurage("farm status " + (dir.path() / "none").string(), dir.path() / "c.txt"), 2);
}

}  // namespace
}  // namespace kurage
