// Particle caches: bit-exact round trips (positions far from the origin and negative included),
// metadata, empty frames, and refusal of missing, truncated and foreign files.
#include "pipeline/io/surface_file.h"
#include "pipeline/io/particle_cache.h"
#include "pipeline/scene.h"
#include "pipeline/sim_frame.h"
#include "sim/simulation.h"
#include "render/surfacing.h"

#include "test_util.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <numeric>
#include <random>
#include <string>
#include <unistd.h>

namespace kurage::pipeline {
namespace {

namespace fs = std::filesystem;

using kurage::test::expectErrorNamingPath;
using kurage::test::TempDir;

// n particles: a dense block plus outliers up to +-1000 m and tiny magnitudes, shuffled ids.
ParticleFrame randomFrame(size_t n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> block(-1.3f, 2.7f), far(-1000.0f, 1000.0f), tiny(-1e-6f, 1e-6f),
      speed(-5.0f, 5.0f);
  ParticleFrame f;
  f.time = 1.0 / 3.0;
  f.frame = 42;
  f.kindNames = {"fluid", "bell", "tentacle"};
  std::vector<int64_t> ids(n);
  std::iota(ids.begin(), ids.end(), int64_t(1) << 40);
  std::shuffle(ids.begin(), ids.end(), rng);
  for (size_t i = 0; i < n; ++i) {
    auto& dist = (i % 10 == 0) ? far : (i % 97 == 0) ? tiny : block;
    f.px.push_back(dist(rng));
    f.py.push_back(dist(rng));
    f.pz.push_back(dist(rng));
    f.vx.push_back(speed(rng));
    f.vy.push_back(speed(rng));
    f.vz.push_back(speed(rng));
    f.id.push_back(ids[i]);
    f.kind.push_back(int32_t(i % 3));
    f.restDensityFactor.push_back(i % 3 == 0 ? 1.0f : 0.37f + 0.11f * float(i % 17));
  }
  // Exact edge values: zero, negative zero, large, a half-way point of the power-of-two grid
  // (frames of three particles or more; the suite under AddressSanitizer caught a write past a
  // one-particle frame here).
  if (n < 3) return f;
  f.px[1] = 0.0f;
  f.py[1] = -0.0f;
  f.pz[1] = 1000.0f;
  f.px[2] = -1000.0f;
  f.py[2] = 0.5f;
  f.pz[2] = -0.5f;
  return f;
}

// The frame with its particles sorted by id.
ParticleFrame sortedById(const ParticleFrame& f) {
  std::vector<size_t> order(f.size());
  std::iota(order.begin(), order.end(), size_t(0));
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return f.id[a] < f.id[b]; });
  ParticleFrame s = f;
  for (size_t i = 0; i < order.size(); ++i) {
    s.px[i] = f.px[order[i]];
    s.py[i] = f.py[order[i]];
    s.pz[i] = f.pz[order[i]];
    s.vx[i] = f.vx[order[i]];
    s.vy[i] = f.vy[order[i]];
    s.vz[i] = f.vz[order[i]];
    s.id[i] = f.id[order[i]];
    s.kind[i] = f.kind[order[i]];
    if (!f.restDensityFactor.empty()) s.restDensityFactor[i] = f.restDensityFactor[order[i]];
  }
  return s;
}

template <typename T>
bool sameBits(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

void expectSameFrame(const ParticleFrame& expected, const ParticleFrame& actual) {
  EXPECT_EQ(actual.time, expected.time);
  EXPECT_EQ(actual.frame, expected.frame);
  EXPECT_EQ(actual.kindNames, expected.kindNames);
  ASSERT_EQ(actual.size(), expected.size());
  EXPECT_TRUE(sameBits(actual.px, expected.px));
  EXPECT_TRUE(sameBits(actual.py, expected.py));
  EXPECT_TRUE(sameBits(actual.pz, expected.pz));
  EXPECT_TRUE(sameBits(actual.vx, expected.vx));
  EXPECT_TRUE(sameBits(actual.vy, expected.vy));
  EXPECT_TRUE(sameBits(actual.vz, expected.vz));
  EXPECT_EQ(actual.id, expected.id);
  EXPECT_EQ(actual.kind, expected.kind);
  if (expected.restDensityFactor.empty())  // written as all 1
    EXPECT_EQ(actual.restDensityFactor, std::vector<float>(expected.size(), 1.0f));
  else
    EXPECT_TRUE(sameBits(actual.restDensityFactor, expected.restDensityFactor));
}

TEST(ParticleCache, RoundTripIsBitExact) {
  TempDir dir;
  const fs::path path = dir.path() / "particles_0042.vdb";
  const ParticleFrame frame = randomFrame(5000, 1);
  writeParticleFrame(path, frame);
  EXPECT_TRUE(fs::exists(path));
  EXPECT_FALSE(fs::exists(path.string() + ".tmp"));
  const ParticleFrame read = readParticleFrame(path);
  expectSameFrame(sortedById(frame), read);
  // The reader's output is sorted by id.
  EXPECT_TRUE(std::is_sorted(read.id.begin(), read.id.end()));
  // Negative zero keeps its sign bit.
  const auto it = std::find(read.id.begin(), read.id.end(), frame.id[1]);
  ASSERT_NE(it, read.id.end());
  EXPECT_TRUE(std::signbit(read.py[size_t(it - read.id.begin())]));
}

TEST(ParticleCache, RoundTripOfSmallAndSpreadFrames) {
  TempDir dir;
  // A single particle, a tight cluster (small voxels) and a flat sheet.
  ParticleFrame one = randomFrame(1, 2);
  ParticleFrame tight = randomFrame(2000, 3);
  for (auto* a : {&tight.px, &tight.py, &tight.pz})
    for (float& x : *a) x = 123.456f + x * 1e-4f;
  ParticleFrame sheet = randomFrame(500, 4);
  std::fill(sheet.pz.begin(), sheet.pz.end(), -7.25f);
  int n = 0;
  for (const ParticleFrame* f : {&one, &tight, &sheet}) {
    const fs::path path = dir.path() / ("frame_" + std::to_string(n++) + ".vdb");
    writeParticleFrame(path, *f);
    expectSameFrame(sortedById(*f), readParticleFrame(path));
  }
}

TEST(ParticleCache, EmptyFrameRoundTrips) {
  TempDir dir;
  const fs::path path = dir.path() / "empty.vdb";
  ParticleFrame frame;
  frame.time = 2.5;
  frame.frame = 3;
  frame.kindNames = {"fluid", "bell"};
  writeParticleFrame(path, frame);
  const ParticleFrame read = readParticleFrame(path);
  EXPECT_EQ(read.size(), 0u);
  expectSameFrame(frame, read);
}

TEST(ParticleCache, MissingTruncatedAndForeignFilesThrowNamingThePath) {
  TempDir dir;
  const fs::path missing = dir.path() / "missing.vdb";
  expectErrorNamingPath([&] { readParticleFrame(missing); }, missing);

  const fs::path text = dir.path() / "text.vdb";
  std::ofstream(text) << "not a vdb\n";
  expectErrorNamingPath([&] { readParticleFrame(text); }, text);

  const fs::path good = dir.path() / "good.vdb";
  writeParticleFrame(good, randomFrame(3000, 5));
  const auto size = fs::file_size(good);
  for (const double fraction : {0.5, 0.05, 0.25, 0.75, 0.95, 0.999}) {
    const fs::path cut = dir.path() / ("cut_" + std::to_string(int(fraction * 1000)) + ".vdb");
    fs::copy_file(good, cut);
    fs::resize_file(cut, static_cast<uintmax_t>(double(size) * fraction));
    expectErrorNamingPath([&] { readParticleFrame(cut); }, cut);
  }

  // A valid .vdb without a "particles" grid (a level set file).
  const fs::path levelSets = dir.path() / "levelsets.vdb";
  const render::LevelSet blob = render::buildMetaballLevelSet({Eigen::Vector3f::Zero()}, render::MetaballParams{});
  writeSurfaceFile(levelSets, {{"fluid", &blob}}, 0.0, 0, "");
  expectErrorNamingPath([&] { readParticleFrame(levelSets); }, levelSets, "wrong kind of file");
}

TEST(ParticleCache, MissingAttributeThrowsNamingIt) {
  TempDir dir;
  const fs::path path = dir.path() / "renamed.vdb";
  writeParticleFrame(path, randomFrame(100, 6));
  // Rename the attribute "kind" to "kinx" in the attribute descriptor (stored uncompressed as a
  // length-prefixed string); the metadata key "kurage:kinds" is left alone.
  std::string bytes;
  {
    std::ifstream in(path, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  const std::string needle = std::string("\x04\0\0\0", 4) + "kind";
  size_t patched = 0;
  for (size_t at = bytes.find(needle); at != std::string::npos; at = bytes.find(needle, at + 1)) {
    bytes[at + needle.size() - 1] = 'x';
    ++patched;
  }
  ASSERT_GT(patched, 0u) << "attribute name not found in the file";
  // Re-seal the checksum, so that the reader gets past it to the missing attribute.
  const std::string checksumKey = "kurage:checksum" + std::string("\x06\0\0\0", 4) + "string" + std::string("\x10\0\0\0", 4);
  const size_t digits = bytes.find(checksumKey) + checksumKey.size();
  bytes.replace(digits, 16, kChecksumPlaceholder);
  sealChecksum(bytes, path);
  std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
  expectErrorNamingPath([&] { readParticleFrame(path); }, path, "kind");
}

TEST(ParticleCache, WriterRefusesInconsistentFrames) {
  TempDir dir;
  const fs::path path = dir.path() / "bad.vdb";
  ParticleFrame frame = randomFrame(10, 7);
  frame.kind.pop_back();
  expectErrorNamingPath([&] { writeParticleFrame(path, frame); }, path);
  frame = randomFrame(10, 7);
  frame.px[3] = std::numeric_limits<float>::quiet_NaN();
  expectErrorNamingPath([&] { writeParticleFrame(path, frame); }, path);
  EXPECT_FALSE(fs::exists(path));
  for (const auto& entry : fs::directory_iterator(fs::path(path).parent_path()))  // .NAME.PID.N.tmp
    EXPECT_NE(entry.path().extension(), ".tmp") << "left behind: " << entry.path();
}

}  // namespace
}  // namespace kurage::pipeline

// The one conversion from the simulation to a frame (pipeline/sim_frame.h): every kind by name,
// and rest density factors relative to each particle's own rest density as built.
namespace kurage::pipeline {
namespace {

TEST(SimFrame, NamesEveryKindAndGivesFactorsOfOneAtRest) {
  const Scene scene = loadScene(test::sourceDir() / "scenes/jellyfish.json");
  const sim::Simulation simulation(scene.sim);
  const ParticleFrame frame = frameFromSimulation(scene, simulation, 7);
  std::vector<std::string> expected{"fluid"};
  for (const sim::BodyParams& b : scene.sim.bodies) expected.push_back(b.name);
  ASSERT_GE(expected.size(), 3u);
  EXPECT_EQ(frame.kindNames, expected);
  EXPECT_EQ(frame.frame, 7);
  ASSERT_EQ(frame.restDensityFactor.size(), frame.size());
  std::vector<int> perKind(frame.kindNames.size(), 0);
  for (size_t i = 0; i < frame.size(); ++i) {
    ASSERT_GE(frame.kind[i], 0);
    ASSERT_LT(size_t(frame.kind[i]), frame.kindNames.size());
    ++perKind[size_t(frame.kind[i])];
    // The bell's margin ring is built heavier than the rest of the bell (its own specific gravity):
    // dividing by the fluid's rest density, as `kurage still` once did, gives its gravity here.
    EXPECT_FLOAT_EQ(frame.restDensityFactor[i], 1.0f) << "particle " << i << " kind " << frame.kind[i];
  }
  for (size_t k = 0; k < perKind.size(); ++k) EXPECT_GT(perKind[k], 0) << frame.kindNames[k];
}

TEST(SimFrame, ABodySceneCacheListsEveryKind) {
  TempDir dir;
  const fs::path scene = test::sourceDir() / "tests/scenes/tiny_jellyfish.json";
  ASSERT_EQ(test::runKurage("sim " + scene.string() + " -o " + dir.path().string() + " --frames 0-0",
                            dir.path() / "log.txt"),
            0);
  const ParticleFrame frame = readParticleFrame(dir.path() / "particles/0000.vdb");
  EXPECT_EQ(frame.kindNames, (std::vector<std::string>{"fluid", "bell", "arm1", "arm2"}));
}

}  // namespace
}  // namespace kurage::pipeline
