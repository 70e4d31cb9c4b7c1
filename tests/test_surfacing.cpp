// Metaball level sets: analytic radius of a single blob, a brute-force check of the summed
// field, meshing (radius, normals, winding, components), thread-count independence, and .vdb
// file round trips and failures.
#include "pipeline/io/surface_file.h"
#include "render/surfacing.h"

#include <Eigen/Geometry>
#include "test_util.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numeric>
#include <ostream>
#include <random>
#include <set>
#include <string>
#include <unistd.h>

namespace kurage::render {

// Readable parameter names in test output.
void PrintTo(const MetaballParams& p, std::ostream* os) {
  *os << "R=" << p.radius << " T=" << p.threshold << " s=" << p.strength << " voxel=" << p.voxelSize;
}

namespace {

namespace fs = std::filesystem;

using kurage::test::TempDir;

double analyticRadius(const MetaballParams& p) {
  return p.radius * std::sqrt(1.0 - std::sqrt(double(p.threshold) / p.strength));
}

// Brute-force metaball field at x.
double field(const std::vector<Eigen::Vector3f>& particles, const Eigen::Vector3d& x, const MetaballParams& p) {
  double f = 0.0;
  for (const Eigen::Vector3f& c : particles) {
    const double q = (x - c.cast<double>()).squaredNorm() / (double(p.radius) * p.radius);
    if (q < 1.0) f += p.strength * (1.0 - q) * (1.0 - q);
  }
  return f;
}

// Distance from `centre` along unit `direction` to the first sign change of the SDF (bisection).
double zeroCrossing(const LevelSet& ls, const Eigen::Vector3f& centre, const Eigen::Vector3f& direction, float maxT) {
  const float step = ls.voxelSize() * 0.25f;
  float a = 0.0f;
  EXPECT_LT(ls.sample(centre), 0.0f);
  for (float t = step; t <= maxT; t += step) {
    if (ls.sample(centre + t * direction) > 0.0f) {
      float lo = a, hi = t;
      for (int i = 0; i < 40; ++i) {
        const float mid = 0.5f * (lo + hi);
        (ls.sample(centre + mid * direction) > 0.0f ? hi : lo) = mid;
      }
      return 0.5 * (lo + hi);
    }
    a = t;
  }
  ADD_FAILURE() << "no zero crossing within " << maxT;
  return -1.0;
}

std::vector<Eigen::Vector3f> randomCluster(size_t n, float halfExtent, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-halfExtent, halfExtent);
  std::vector<Eigen::Vector3f> out(n);
  for (auto& p : out) p = Eigen::Vector3f(u(rng), u(rng), u(rng));
  return out;
}

// Values of the level set at every voxel centre of the box [lo, hi] (world).
std::vector<float> sampleVoxelCentres(const LevelSet& ls, const Eigen::Vector3f& lo, const Eigen::Vector3f& hi) {
  const float h = ls.voxelSize();
  std::vector<float> out;
  for (int i = int(std::floor(lo.x() / h)); i <= int(std::ceil(hi.x() / h)); ++i)
    for (int j = int(std::floor(lo.y() / h)); j <= int(std::ceil(hi.y() / h)); ++j)
      for (int k = int(std::floor(lo.z() / h)); k <= int(std::ceil(hi.z() / h)); ++k)
        out.push_back(ls.sample(Eigen::Vector3f(i * h, j * h, k * h)));
  return out;
}

const MetaballParams kParamsA{};  // R = 2, T = 0.6, s = 1, voxel 0.25
const MetaballParams kParamsB{1.0f, 0.2f, 1.5f, 0.1f, 3.0f};

class SingleBlob : public ::testing::TestWithParam<MetaballParams> {};

TEST_P(SingleBlob, ZeroCrossingAtAnalyticRadius) {
  const MetaballParams params = GetParam();
  const Eigen::Vector3f centre(0.13f, -0.07f, 0.21f);
  const LevelSet ls = buildMetaballLevelSet({centre}, params);
  ASSERT_FALSE(ls.empty());
  EXPECT_FLOAT_EQ(ls.voxelSize(), params.voxelSize);
  const double r0 = analyticRadius(params);
  EXPECT_LT(ls.sample(centre), 0.0f);
  EXPECT_GT(ls.sample(centre + Eigen::Vector3f(float(r0) + params.voxelSize, 0, 0)), 0.0f);
  // Far outside: the background, half width in voxels times the voxel size.
  EXPECT_FLOAT_EQ(ls.sample(centre + Eigen::Vector3f(10 * params.radius, 0, 0)), params.halfWidth * params.voxelSize);
  const Eigen::Vector3f directions[] = {{1, 0, 0}, {0, -1, 0}, {0, 0, 1}, Eigen::Vector3f(1, 1, -1).normalized()};
  for (const Eigen::Vector3f& d : directions) {
    const double r = zeroCrossing(ls, centre, d, params.radius);
    EXPECT_NEAR(r, r0, 0.5 * params.voxelSize) << "direction " << d.transpose();
  }
  // Inside, the SDF approximates minus the distance to the sphere.
  EXPECT_NEAR(ls.sample(centre + Eigen::Vector3f(0, float(r0) - 2 * params.voxelSize, 0)), -2 * params.voxelSize,
              0.5 * params.voxelSize);
}

TEST_P(SingleBlob, MeshOnAnalyticSphereWithOutwardNormalsAndCounterClockwiseFaces) {
  const MetaballParams params = GetParam();
  const Eigen::Vector3f centre(-0.31f, 0.52f, 0.08f);
  const TriangleMesh mesh = meshLevelSet(buildMetaballLevelSet({centre}, params));
  ASSERT_GT(mesh.triangles.size(), 50u);
  ASSERT_EQ(mesh.normals.size(), mesh.positions.size());
  const double r0 = analyticRadius(params);
  for (size_t i = 0; i < mesh.positions.size(); ++i) {
    const Eigen::Vector3f radial = mesh.positions[i] - centre;
    EXPECT_NEAR(radial.norm(), r0, params.voxelSize);
    EXPECT_NEAR(mesh.normals[i].norm(), 1.0f, 1e-4f);
    EXPECT_GT(mesh.normals[i].dot(radial.normalized()), 0.9f) << "vertex " << i;
  }
  size_t agreeing = 0;
  for (const Eigen::Vector3i& t : mesh.triangles) {
    for (int c = 0; c < 3; ++c) ASSERT_TRUE(t[c] >= 0 && size_t(t[c]) < mesh.positions.size());
    const Eigen::Vector3f& a = mesh.positions[size_t(t[0])];
    const Eigen::Vector3f& b = mesh.positions[size_t(t[1])];
    const Eigen::Vector3f& c = mesh.positions[size_t(t[2])];
    const Eigen::Vector3f face = (b - a).cross(c - a);
    const Eigen::Vector3f vertexNormals = mesh.normals[size_t(t[0])] + mesh.normals[size_t(t[1])] + mesh.normals[size_t(t[2])];
    if (face.dot(vertexNormals) > 0.0f) ++agreeing;
  }
  EXPECT_GT(double(agreeing), 0.95 * double(mesh.triangles.size()));
  // Closed surface: the signed volume (divergence theorem) is positive and near the sphere's.
  double volume = 0.0;
  for (const Eigen::Vector3i& t : mesh.triangles) {
    const Eigen::Vector3d a = (mesh.positions[size_t(t[0])] - centre).cast<double>();
    const Eigen::Vector3d b = (mesh.positions[size_t(t[1])] - centre).cast<double>();
    const Eigen::Vector3d c = (mesh.positions[size_t(t[2])] - centre).cast<double>();
    volume += a.dot(b.cross(c)) / 6.0;
  }
  const double sphere = 4.0 / 3.0 * M_PI * r0 * r0 * r0;
  EXPECT_NEAR(volume, sphere, 0.1 * sphere);
}

TEST_P(SingleBlob, EveryBandVoxelIsCloseToTheDistanceToTheSphere) {
  // The band's distances (nearest estimated surface point, render/surfacing.cpp) against the
  // exact distance to the analytic sphere, at every voxel centre of the band.
  const MetaballParams params = GetParam();
  const Eigen::Vector3f centre(0.13f, -0.07f, 0.21f);
  const LevelSet ls = buildMetaballLevelSet({centre}, params);
  const double r0 = analyticRadius(params);
  const float h = params.voxelSize;
  const float background = params.halfWidth * h;
  const int n = int(std::ceil((r0 + background) / h)) + 2;
  size_t band = 0;
  double worst = 0.0;
  for (int i = -n; i <= n; ++i)
    for (int j = -n; j <= n; ++j)
      for (int k = -n; k <= n; ++k) {
        const Eigen::Vector3f x(i * h, j * h, k * h);
        const float sdf = ls.sample(x);
        const double exact = (x - centre).cast<double>().norm() - r0;
        if (std::abs(exact) < background - h) {
          EXPECT_LT(std::abs(sdf), background) << "voxel " << i << " " << j << " " << k << " left out of the band";
        }
        if (std::abs(sdf) >= background) continue;
        ++band;
        worst = std::max(worst, std::abs(sdf - exact));
        EXPECT_NEAR(sdf, exact, 0.25 * h) << "voxel " << i << " " << j << " " << k;
      }
  EXPECT_GT(band, 500u);
  RecordProperty("worst_error_in_voxels", std::to_string(worst / h));
}

INSTANTIATE_TEST_SUITE_P(Metaball, SingleBlob, ::testing::Values(kParamsA, kParamsB),
                         [](const ::testing::TestParamInfo<MetaballParams>& info) {
                           return info.index == 0 ? std::string("R2_T06") : std::string("R1_T02");
                         });

// Union-find count of the connected components of a mesh (by shared vertices).
size_t countComponents(const TriangleMesh& mesh) {
  std::vector<size_t> parent(mesh.positions.size());
  std::iota(parent.begin(), parent.end(), size_t(0));
  const auto find = [&](size_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  for (const Eigen::Vector3i& t : mesh.triangles) {
    parent[find(size_t(t[1]))] = find(size_t(t[0]));
    parent[find(size_t(t[2]))] = find(size_t(t[0]));
  }
  std::set<size_t> roots;
  for (size_t i = 0; i < parent.size(); ++i) roots.insert(find(i));
  return roots.size();
}

TEST(Metaball, TwoFarParticlesGiveTwoBlobs) {
  const MetaballParams params = kParamsA;
  const Eigen::Vector3f a(0, 0, 0), b(6, 1, -2);
  const LevelSet ls = buildMetaballLevelSet({a, b}, params);
  EXPECT_LT(ls.sample(a), 0.0f);
  EXPECT_LT(ls.sample(b), 0.0f);
  EXPECT_GT(ls.sample(0.5f * (a + b)), 0.0f);
  EXPECT_EQ(countComponents(meshLevelSet(ls)), 2u);
  // Two close particles merge into one.
  EXPECT_EQ(countComponents(meshLevelSet(buildMetaballLevelSet({a, Eigen::Vector3f(1.2f, 0, 0)}, params))), 1u);
}

TEST(Metaball, SignAgreesWithBruteForceFieldNearTheSurface) {
  for (const MetaballParams& params : {kParamsA, kParamsB}) {
    const std::vector<Eigen::Vector3f> particles = randomCluster(60, 3.0f * params.radius, 7);
    const LevelSet ls = buildMetaballLevelSet(particles, params);
    const float h = params.voxelSize;
    const float reach = 4.0f * params.radius;
    size_t inside = 0, outside = 0;
    for (int i = int(-reach / h); i <= int(reach / h); ++i)
      for (int j = int(-reach / h); j <= int(reach / h); ++j)
        for (int k = int(-reach / h); k <= int(reach / h); ++k) {
          const Eigen::Vector3f x(i * h, j * h, k * h);
          const float sdf = ls.sample(x);
          if (std::abs(sdf) >= h) continue;
          const double f = field(particles, x.cast<double>(), params);
          if (sdf < -0.5f * h) {
            EXPECT_GT(f, params.threshold) << "voxel " << i << " " << j << " " << k;
            ++inside;
          } else if (sdf > 0.5f * h) {
            EXPECT_LT(f, params.threshold) << "voxel " << i << " " << j << " " << k;
            ++outside;
          }
        }
    EXPECT_GT(inside, 100u);
    EXPECT_GT(outside, 100u);
  }
}

TEST(Metaball, DenseBlockIsInsideDeepBelowTheBand) {
  const MetaballParams params{1.0f, 0.6f, 1.0f, 0.25f, 3.0f};
  std::vector<Eigen::Vector3f> particles;
  for (int i = 0; i < 20; ++i)
    for (int j = 0; j < 20; ++j)
      for (int k = 0; k < 20; ++k) particles.emplace_back(0.5f * i, 0.5f * j, 0.5f * k);
  const LevelSet ls = buildMetaballLevelSet(particles, params);
  const float background = params.halfWidth * params.voxelSize;
  // Exactly -background in the middle: the interior is flood-filled, not part of the band.
  EXPECT_FLOAT_EQ(ls.sample(Eigen::Vector3f(4.75f, 4.75f, 4.75f)), -background);
  EXPECT_FLOAT_EQ(ls.sample(Eigen::Vector3f(2.0f, 7.0f, 5.0f)), -background);
  EXPECT_FLOAT_EQ(ls.sample(Eigen::Vector3f(4.75f, 4.75f, 20.0f)), background);
  // Along +z from the top layer, the SDF grows by about one voxel per voxel.
  const float top = float(zeroCrossing(ls, Eigen::Vector3f(4.75f, 4.75f, 9.5f), Eigen::Vector3f(0, 0, 1), 1.0f));
  for (const float d : {-0.5f, -0.25f, 0.25f, 0.5f}) {
    EXPECT_NEAR(ls.sample(Eigen::Vector3f(4.75f, 4.75f, 9.5f + top + d)), d, 0.3f * params.voxelSize);
  }
}

TEST(Metaball, EmptyInputGivesEmptyLevelSet) {
  const LevelSet ls = buildMetaballLevelSet({}, kParamsA);
  EXPECT_TRUE(ls.empty());
  EXPECT_EQ(ls.activeVoxelCount(), 0u);
  EXPECT_TRUE(meshLevelSet(ls).triangles.empty());
  EXPECT_TRUE(LevelSet().empty());
}

TEST(Metaball, RejectsBadParameters) {
  MetaballParams bad = kParamsA;
  bad.threshold = 2.0f;  // above the strength: no surface at all
  EXPECT_THROW(buildMetaballLevelSet({Eigen::Vector3f::Zero()}, bad), std::invalid_argument);
  bad = kParamsA;
  bad.voxelSize = 0.0f;
  EXPECT_THROW(buildMetaballLevelSet({Eigen::Vector3f::Zero()}, bad), std::invalid_argument);
}

TEST(Metaball, SameGridForOneAndTwoThreads) {
  const MetaballParams params{0.4f, 0.6f, 1.0f, 0.1f, 3.0f};
  const std::vector<Eigen::Vector3f> particles = randomCluster(3000, 1.5f, 11);
  const auto build = [&](int threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(threads));
    return buildMetaballLevelSet(particles, params);
  };
  const LevelSet one = build(1);
  const LevelSet two = build(2);
  EXPECT_EQ(one.activeVoxelCount(), two.activeVoxelCount());
  const Eigen::Vector3f lo = Eigen::Vector3f::Constant(-2.0f), hi = Eigen::Vector3f::Constant(2.0f);
  const std::vector<float> a = sampleVoxelCentres(one, lo, hi), b = sampleVoxelCentres(two, lo, hi);
  ASSERT_EQ(a.size(), b.size());
  size_t differing = 0;
  for (size_t i = 0; i < a.size(); ++i) differing += (a[i] != b[i]);
  EXPECT_EQ(differing, 0u);
}

TEST(LevelSetFile, RoundTripKeepsNamesValuesAndMetadata) {
  TempDir dir;
  const fs::path path = dir.path() / "frame_0007.vdb";
  const LevelSet fluid = buildMetaballLevelSet(randomCluster(200, 2.0f, 3), kParamsA);
  const LevelSet bell = buildMetaballLevelSet({Eigen::Vector3f(5, 5, 5)}, kParamsB);
  const LevelSet none = buildMetaballLevelSet({}, kParamsA);
  pipeline::writeSurfaceFile(path, {{"fluid", &fluid}, {"bell", &bell}, {"emitter", &none}}, 0.4375, 7, "0123456789abcdef");
  EXPECT_TRUE(fs::exists(path));
  EXPECT_FALSE(fs::exists(path.string() + ".tmp"));

  LevelSetFileInfo info;
  const std::map<std::string, LevelSet> read = pipeline::readSurfaceFile(path, {"surface", "0123456789abcdef", 7}, &info);
  EXPECT_EQ(info.time, 0.4375);
  EXPECT_EQ(info.frame, 7);
  ASSERT_EQ(read.size(), 3u);
  ASSERT_TRUE(read.count("fluid") && read.count("bell") && read.count("emitter"));
  EXPECT_TRUE(read.at("emitter").empty());
  EXPECT_EQ(read.at("fluid").activeVoxelCount(), fluid.activeVoxelCount());
  EXPECT_EQ(read.at("bell").activeVoxelCount(), bell.activeVoxelCount());
  EXPECT_FLOAT_EQ(read.at("bell").voxelSize(), kParamsB.voxelSize);
  const Eigen::Vector3f lo = Eigen::Vector3f::Constant(-5.0f), hi = Eigen::Vector3f::Constant(5.0f);
  EXPECT_EQ(sampleVoxelCentres(read.at("fluid"), lo, hi), sampleVoxelCentres(fluid, lo, hi));
  EXPECT_EQ(sampleVoxelCentres(read.at("bell"), Eigen::Vector3f::Constant(4.0f), Eigen::Vector3f::Constant(6.0f)),
            sampleVoxelCentres(bell, Eigen::Vector3f::Constant(4.0f), Eigen::Vector3f::Constant(6.0f)));
  EXPECT_EQ(pipeline::readSurfaceFile(path).size(), 3u);
  EXPECT_EQ(info.tags.at("kurage:stage"), "surface");
}

// Expects `call` to throw std::runtime_error whose message names `path`.
template <typename Call>
void expectErrorNamingPath(Call call, const fs::path& path) {
  try {
    call();
    ADD_FAILURE() << "no exception for " << path;
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(path.string()), std::string::npos) << e.what();
  }
}

TEST(LevelSetFile, MissingTruncatedOrForeignFilesThrowNamingThePath) {
  TempDir dir;
  expectErrorNamingPath([&] { pipeline::readSurfaceFile(dir.path() / "missing.vdb"); }, dir.path() / "missing.vdb");

  const fs::path text = dir.path() / "text.vdb";
  std::ofstream(text) << "this is not a vdb file\n";
  expectErrorNamingPath([&] { pipeline::readSurfaceFile(text); }, text);

  const fs::path good = dir.path() / "good.vdb";
  const LevelSet fluid = buildMetaballLevelSet(randomCluster(100, 2.0f, 5), kParamsA);
  pipeline::writeSurfaceFile(good, {{"fluid", &fluid}}, 1.0, 1, "");
  const auto size = fs::file_size(good);
  for (const double fraction : {0.5, 0.1, 0.9, 0.99}) {
    const fs::path cut = dir.path() / ("cut_" + std::to_string(int(fraction * 100)) + ".vdb");
    fs::copy_file(good, cut);
    fs::resize_file(cut, static_cast<uintmax_t>(double(size) * fraction));
    expectErrorNamingPath([&] { pipeline::readSurfaceFile(cut); }, cut);
  }

  // Writing into a directory that does not exist fails with the path too.
  const fs::path nowhere = dir.path() / "no" / "such" / "dir.vdb";
  expectErrorNamingPath([&] { pipeline::writeSurfaceFile(nowhere, {{"fluid", &fluid}}, 0.0, 0, ""); }, nowhere);
}

TEST(LevelSetFile, VersionIsReported) {
  const std::string version = openvdbVersion();
  EXPECT_TRUE(!version.empty() && std::isdigit(static_cast<unsigned char>(version[0])) &&
              version.find('.') != std::string::npos)
      << version;
}

}  // namespace
}  // namespace kurage::render
