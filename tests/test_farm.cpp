// kurage farm against a real Slurm (label cluster): a private single-node cluster started by the
// CTest fixture slurm_start (tests/slurm_local.sh, root needed) and stopped by slurm_stop.
// The farmed frames are byte-identical to `kurage run`'s and the caches hold the same contents; a
// failed task cancels the merge, `kurage farm status` names the missing frames, and resubmitting
// runs only the failed chunk.
#include "pipeline/io/files.h"
#include "pipeline/io/particle_cache.h"

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
    EXPECT_TRUE(x.px == y.px && x.py == y.py && x.pz == y.pz && x.vx == y.vx && x.vy == y.vy && x.vz == y.vz &&
                x.id == y.id && x.kind == y.kind && x.restDensityFactor == y.restDensityFactor &&
                x.kindNames == y.kindNames && x.sceneHash == y.sceneHash && x.time == y.time && x.frame == y.frame)
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
  for (const char* stage : {"surface", "render"}) {  // every task's frames, in frame order
    EXPECT_EQ(record["stages"][stage]["per_frame"]["frame"], nlohmann::json({0, 1, 2, 3, 4})) << stage;
    EXPECT_EQ(record["stages"][stage]["per_frame"]["seconds"].size(), 5u) << stage;
  }
  EXPECT_GT(record["stages"]["sim"]["seconds"].get<double>(), 0.0);
  EXPECT_TRUE(fs::exists(out / "tiny_dam_break.mp4"));
  // the merge writes the run's page, showing the film it encoded
  ASSERT_TRUE(fs::exists(out / "report.html"));
  EXPECT_NE(readText(out / "report.html").find("<source src=\"tiny_dam_break.mp4\""), std::string::npos);
  const std::string status = run((test::binaryDir() / "kurage").string() + " farm status " + out.string());
  EXPECT_NE(status.find("merge  job"), std::string::npos) << status;
  EXPECT_NE(status.find("COMPLETED"), std::string::npos) << status;
  EXPECT_NE(status.find("missing frames: none"), std::string::npos) << status;
}

TEST_F(Farm, AFailedTaskCancelsTheMergeAndAResubmitRunsOnlyWhatIsMissing) {
  const fs::path out = dir_.path() / "farmed";
  // The caches exist (so the farm submits no simulation), but frame 3 cannot be written (a folder
  // stands where its PNG goes): the task of frames 2-3 fails after making frame 2.
  ASSERT_EQ(test::runKurage("sim " + kScene.string() + " -o " + out.string(), dir_.path() / "sim.txt"), 0);
  const fs::path blocked = pipeline::frameFile(out / "frames", 3, "png");
  fs::create_directories(blocked / "in_the_way");
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
  EXPECT_NE(status.find("missing frames: 3 (tasks 1)"), std::string::npos) << status;
  EXPECT_FALSE(fs::exists(out / "run.json") && nlohmann::json::parse(readText(out / "run.json")).contains("farm"));

  // Mended, and submitted again: only chunk 1 runs, and in it only frame 3 (frame 2 is whole and
  // stamped with this scene's render hash, so the rerun task keeps it), then the merge.
  fs::remove_all(blocked);
  const auto before0 = fs::last_write_time(pipeline::frameFile(out / "frames", 0, "png"));
  const auto before2 = fs::last_write_time(pipeline::frameFile(out / "frames", 2, "png"));
  ASSERT_EQ(test::runKurage("farm " + kScene.string() + " -o " + out.string() + " --frames-per-task 2 --submit",
                            dir_.path() / "farm2.txt"),
            0)
      << readText(dir_.path() / "farm2.txt");
  jobs = nlohmann::json::parse(readText(out / "farm/jobs.json"));
  EXPECT_FALSE(jobs.contains("sim"));
  EXPECT_EQ(jobs["frame_tasks"], nlohmann::json::array({1}));
  waitForFarm(out);
  EXPECT_EQ(fs::last_write_time(pipeline::frameFile(out / "frames", 0, "png")), before0) << "frame 0 was redone";
  EXPECT_EQ(fs::last_write_time(pipeline::frameFile(out / "frames", 2, "png")), before2) << "frame 2 was redone";
  expectSameFrames(local_, out, 0, 4);
  EXPECT_NE(run((test::binaryDir() / "kurage").string() + " farm status " + out.string()).find("missing frames: none"),
            std::string::npos);
  // A damaged cache is not counted as done (status reads each file's checksum and stamp).
  pipeline::writeTextAtomic(pipeline::frameFile(out / "particles", 4, "vdb"), "not an OpenVDB file");
  const std::string after = run((test::binaryDir() / "kurage").string() + " farm status " + out.string());
  EXPECT_NE(after.find("caches 4 of 5"), std::string::npos) << after;
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

TEST(FarmCommand, FlagsShapeTheScripts) {
  // --frames-per-task and --max-tasks cut the frames into the array's chunks; --partition,
  // --time-limit and --sbatch-arg become #SBATCH lines of every script; the frame tasks run the
  // stage table's per-frame stages (surface, render) on their chunk.
  test::TempDir dir;
  const fs::path out = dir.path() / "out";
  ASSERT_EQ(test::runKurage("farm " + kScene.string() + " -o " + out.string() +
                                " --frames-per-task 2 --partition gpu --time-limit 00:10:00 --sbatch-arg --mem=1G"
                                " --sbatch-arg '--account=lab x'",
                            dir.path() / "a.txt"), 0) << readText(dir.path() / "a.txt");
  const nlohmann::json plan = nlohmann::json::parse(readText(out / "farm/plan.json"));
  EXPECT_EQ(plan["chunks"], nlohmann::json::parse("[[0,1],[2,3],[4,4]]"));
  for (const char* script : {"sim.sbatch", "frames.sbatch", "merge.sbatch"}) {
    const std::string text = readText(out / "farm" / script);
    for (const char* line : {"#SBATCH --partition=gpu\n", "#SBATCH --time=00:10:00\n", "#SBATCH --mem=1G\n",
                             "#SBATCH --account=lab x\n"})
      EXPECT_NE(text.find(line), std::string::npos) << script << " lacks " << line;
  }
  const std::string frames = readText(out / "farm/frames.sbatch");
  EXPECT_NE(frames.find("chunks=(0-1 2-3 4-4)"), std::string::npos) << frames;
  EXPECT_LT(frames.find(" surface "), frames.find(" render ")) << frames;
  EXPECT_NE(frames.find("--task \"render-$range\""), std::string::npos) << frames;
  ASSERT_EQ(test::runKurage("farm " + kScene.string() + " -o " + out.string() + " --frames-per-task 1 --max-tasks 2", dir.path() / "b.txt"), 0);
  EXPECT_EQ(nlohmann::json::parse(readText(out / "farm/plan.json"))["chunks"], nlohmann::json::parse("[[0,2],[3,4]]"));
}

TEST(FarmCommand, AFailingSbatchIsPassedOnAndJobsJsonKeepsWhatWasQueued) {
  // A fake sbatch that queues the first script and refuses the second, as Slurm does for an
  // unknown partition: kurage exits 1 with sbatch's own message, and jobs.json names the job
  // that was queued (so it can be cancelled).
  test::TempDir dir;
  const fs::path bin = dir.path() / "bin";
  fs::create_directories(bin);
  pipeline::writeTextAtomic(bin / "sbatch",
                            "#!/bin/sh\n"
                            "if [ -e \"$0.called\" ]; then\n"
                            "  echo 'sbatch: error: invalid partition specified: nope' >&2; exit 1\n"
                            "fi\n"
                            "touch \"$0.called\"; echo 4242\n");
  fs::permissions(bin / "sbatch", fs::perms::owner_all);
  const fs::path out = dir.path() / "out";
  const std::string command = "PATH=" + bin.string() + ":/usr/bin:/bin " + (test::binaryDir() / "kurage").string() +
                              " farm " + kScene.string() + " -o " + out.string() + " --partition nope --submit > " +
                              (dir.path() / "log.txt").string() + " 2>&1";
  const int status = std::system(command.c_str());
  const std::string log = readText(dir.path() / "log.txt");
  EXPECT_EQ(WEXITSTATUS(status), 1) << log;
  EXPECT_NE(log.find("invalid partition specified: nope"), std::string::npos) << log;
  EXPECT_NE(log.find(out.string() + "/farm"), std::string::npos) << "the scripts' folder is not named: " << log;
  ASSERT_TRUE(fs::exists(out / "farm/jobs.json"));
  const nlohmann::json jobs = nlohmann::json::parse(readText(out / "farm/jobs.json"));
  EXPECT_EQ(jobs["sim"], "4242");
  EXPECT_FALSE(jobs.contains("frames"));
  EXPECT_FALSE(jobs.contains("merge"));
}

}  // namespace
}  // namespace kurage
