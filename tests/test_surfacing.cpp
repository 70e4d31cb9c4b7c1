// Metaball level sets: analytic radius of a single blob, a brute-force check of the summed
// field, meshing (radius, normals, winding, components), thread-count independence, and .vdb
// file round trips and failures.
#include "pipeline/io/surface_file.h"
#include "pipeline/sim_frame.h"
#include "pipeline/stages.h"
#include "render/airborne.h"
#include "render/anisotropy.h"
#include "render/surfacing.h"
#include "sim/body_shapes.h"

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

// Isotropic metaball parameters (half width 3 voxels).
MetaballParams metaball(float radius, float threshold, float strength, float voxelSize) {
  MetaballParams p;
  p.radius = radius;
  p.threshold = threshold;
  p.strength = strength;
  p.voxelSize = voxelSize;
  p.halfWidth = 3.0f;
  return p;
}

const MetaballParams kParamsA{};  // R = 2, T = 0.6, s = 1, voxel 0.25
const MetaballParams kParamsB = metaball(1.0f, 0.2f, 1.5f, 0.1f);

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
  const MetaballParams params = metaball(1.0f, 0.6f, 1.0f, 0.25f);
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
  const MetaballParams params = metaball(0.4f, 0.6f, 1.0f, 0.1f);
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

TEST(Metaball, RadiusScalesShrinkEachBlobAndScalesOfOneChangeNothing) {
  // One blob at half its radius has the analytic surface of R / 2; all scales 1 give the very
  // grid of the unscaled call; a scale outside (0, 1] or a wrong count is refused.
  const MetaballParams params = metaball(2.0f, 0.5f, 1.0f, 0.1f);
  const Eigen::Vector3f centre(0.13f, -0.07f, 0.21f);
  const LevelSet half = buildMetaballLevelSet({centre}, {0.5f}, params);
  const double r0 = 0.5 * analyticRadius(params);
  for (const Eigen::Vector3f& d : {Eigen::Vector3f(1, 0, 0), Eigen::Vector3f(0, 0, -1)})
    EXPECT_NEAR(zeroCrossing(half, centre, d, params.radius), r0, 0.5 * params.voxelSize);
  const std::vector<Eigen::Vector3f> particles = randomCluster(500, 1.5f, 7);
  const LevelSet plain = buildMetaballLevelSet(particles, params);
  const LevelSet ones = buildMetaballLevelSet(particles, std::vector<float>(particles.size(), 1.0f), params);
  const Eigen::Vector3f lo = Eigen::Vector3f::Constant(-3.5f), hi = Eigen::Vector3f::Constant(3.5f);
  EXPECT_EQ(plain.activeVoxelCount(), ones.activeVoxelCount());
  EXPECT_TRUE(sampleVoxelCentres(plain, lo, hi) == sampleVoxelCentres(ones, lo, hi));
  EXPECT_THROW(buildMetaballLevelSet({centre}, {0.0f}, params), std::invalid_argument);
  EXPECT_THROW(buildMetaballLevelSet({centre}, {kMaxRadiusScale * 1.01f}, params), std::invalid_argument);
  EXPECT_THROW(buildMetaballLevelSet({centre}, {1.0f, 1.0f}, params), std::invalid_argument);
}

TEST(Metaball, RadiusScalesAboveOneGrowABlobPastR) {
  // A blob at twice its radius, beside one at R: its surface is the analytic one of 2 R (the
  // bins' reach follows the largest scale), the other's stays at R's, with isotropic and
  // anisotropic kernels alike.
  for (const MetaballKernel kernel : {MetaballKernel::Isotropic, MetaballKernel::Anisotropic}) {
    MetaballParams params = metaball(1.0f, 0.5f, 1.0f, 0.05f);
    params.kernel = kernel;
    const Eigen::Vector3f big(0.13f, -0.07f, 0.21f), small(6.0f, 0.0f, 0.0f);
    const LevelSet ls = buildMetaballLevelSet({big, small}, {2.0f, 1.0f}, params);
    const double r0 = analyticRadius(params);
    for (const Eigen::Vector3f& d : {Eigen::Vector3f(-1, 0, 0), Eigen::Vector3f(0, 0, -1), Eigen::Vector3f(0, 1, 0)})
      EXPECT_NEAR(zeroCrossing(ls, big, d, 2.0f * params.radius), 2.0 * r0, 0.5 * params.voxelSize);
    EXPECT_NEAR(zeroCrossing(ls, small, Eigen::Vector3f(1, 0, 0), params.radius), r0, 0.5 * params.voxelSize);
  }
}

TEST(Metaball, StretchScalesFollowTheVolumeAndLeaveUnstretchedParticlesAlone) {
  EXPECT_TRUE(stretchRadiusScales({}).empty());
  EXPECT_TRUE(stretchRadiusScales({1.0f, 1.3f, 1.0f}).empty());  // at rest or compressed: R, no scales
  const std::vector<float> scales = stretchRadiusScales({1.0f, 0.125f, 1.0f / 1.728f, 0.001f, 2.0f});
  ASSERT_EQ(scales.size(), 5u);
  EXPECT_EQ(scales[0], 1.0f);
  EXPECT_FLOAT_EQ(scales[1], 2.0f);
  EXPECT_FLOAT_EQ(scales[2], 1.2f);
  EXPECT_EQ(scales[3], kMaxRadiusScale);
  EXPECT_EQ(scales[4], 1.0f);
  EXPECT_THROW(stretchRadiusScales({0.0f}), std::invalid_argument);
  EXPECT_THROW(stretchRadiusScales({std::nanf("")}), std::invalid_argument);
}

TEST(Airborne, AJetAboveAPoolShrinksWhileStillAndDenseWaterKeepsItsRadius) {
  // A still pool 10 x 10 x 4 m at 0.5 m spacing with a fast particle deep inside it, and a jet
  // above it: 4 discs of radius 0.8 m (the jellyfish's nozzles), 0.5 m apart, falling at 5 m/s.
  // The jet gets the airborne radius; the pool, its surface, its corners and the fast particle
  // inside keep R exactly; a jet slower than speed_min keeps R; disabled, everything keeps R.
  const float spacing = 0.5f, R = 2.0f;
  std::vector<Eigen::Vector3f> positions, velocities;
  for (int i = 0; i < 20; ++i)
    for (int j = 0; j < 20; ++j)
      for (int k = 0; k < 8; ++k) {
        positions.emplace_back(0.25f + spacing * i, 0.25f + spacing * j, 0.25f + spacing * k);
        velocities.emplace_back(0, 0, 0);
      }
  const size_t deep = 10 * 160 + 10 * 8 + 3;  // (5.25, 5.25, 1.75)
  velocities[deep] = {0, 0, -5};
  const size_t pool = positions.size();
  for (int k = 0; k < 4; ++k)
    for (int i = -2; i <= 2; ++i)
      for (int j = -2; j <= 2; ++j)
        if (std::hypot(float(i), float(j)) * spacing <= 0.8f) {
          positions.emplace_back(5.0f + spacing * i, 5.0f + spacing * j, 6.5f + spacing * k);
          velocities.emplace_back(0, 0, -5);
        }
  AirborneParams params;
  params.enabled = true;
  const std::vector<float> scales = airborneRadiusScales(positions, velocities, R, spacing, params);
  ASSERT_EQ(scales.size(), positions.size());
  for (size_t i = 0; i < pool; ++i) ASSERT_EQ(scales[i], 1.0f) << "pool particle " << i;
  for (size_t i = pool; i < positions.size(); ++i) EXPECT_FLOAT_EQ(scales[i], params.radius / R) << "jet particle " << i;
  std::vector<Eigen::Vector3f> slow = velocities;
  for (size_t i = pool; i < slow.size(); ++i) slow[i] = {0, 0, -0.5f * params.speedMin};
  for (const float s : airborneRadiusScales(positions, slow, R, spacing, params)) ASSERT_EQ(s, 1.0f);
  params.enabled = false;
  for (const float s : airborneRadiusScales(positions, velocities, R, spacing, params)) ASSERT_EQ(s, 1.0f);
  params.enabled = true;
  params.radius = 2.5f;  // above R
  EXPECT_THROW(airborneRadiusScales(positions, velocities, R, spacing, params), std::invalid_argument);
}

// Exact signed distance to the box [lo, hi], negative inside.
double boxDistance(const Eigen::Vector3d& x, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  const Eigen::Vector3d d = (lo - x).cwiseMax(x - hi);
  return d.cwiseMax(0.0).norm() + std::min(d.maxCoeff(), 0.0);
}

TEST(ClipToBox, BlobCutByABoxMatchesTheCsgOfTheExactDistances) {
  // A single blob (a sphere of radius r0) cut by a box through its centre region: every band
  // voxel is max(sphere, box) of the exact distances within the metaball's own 0.25 voxel.
  const MetaballParams params = kParamsA;
  const Eigen::Vector3f centre(0.13f, -0.07f, 0.21f);
  LevelSet ls = buildMetaballLevelSet({centre}, params);
  const Eigen::Vector3f lo(-0.4f, -2.0f, -0.3f), hi(2.0f, 0.5f, 2.0f);
  intersectWithBox(ls, lo, hi);
  const double r0 = analyticRadius(params);
  const float h = params.voxelSize;
  const float background = params.halfWidth * h;
  size_t band = 0;
  for (int i = -12; i <= 12; ++i)
    for (int j = -12; j <= 12; ++j)
      for (int k = -12; k <= 12; ++k) {
        const Eigen::Vector3f x(i * h, j * h, k * h);
        const double exact = std::max((x - centre).cast<double>().norm() - r0,
                                      boxDistance(x.cast<double>(), lo.cast<double>(), hi.cast<double>()));
        const float sdf = ls.sample(x);
        if (std::abs(exact) < background - h) {
          ASSERT_LT(std::abs(sdf), background) << "voxel " << i << " " << j << " " << k << " left out of the band";
        }
        if (std::abs(sdf) >= background) {
          EXPECT_EQ(sdf > 0.0f, exact > 0.0) << "voxel " << i << " " << j << " " << k;
          continue;
        }
        ++band;
        EXPECT_NEAR(sdf, exact, 0.25 * h) << "voxel " << i << " " << j << " " << k;
      }
  EXPECT_GT(band, 500u);
  // The cut faces are where the box says, along the axes through the centre.
  EXPECT_NEAR(zeroCrossing(ls, centre, {-1, 0, 0}, 2.0f), centre.x() - lo.x(), 0.05 * h);
  EXPECT_NEAR(zeroCrossing(ls, centre, {0, 1, 0}, 2.0f), hi.y() - centre.y(), 0.05 * h);
  EXPECT_NEAR(zeroCrossing(ls, centre, {0, 0, -1}, 2.0f), centre.z() - lo.z(), 0.05 * h);
  EXPECT_NEAR(zeroCrossing(ls, centre, {1, 0, 0}, 2.0f), r0, 0.5 * h);  // the sphere's side, uncut
}

TEST(ClipToBox, DeepInteriorCutByAFaceGetsTheExactDistanceToIt) {
  // A dense block whose inside is flood-filled (-background, no band) is cut well inside: the new
  // faces run through the old interior, where the distance is the box's own, exactly.
  const MetaballParams params = metaball(1.0f, 0.6f, 1.0f, 0.25f);
  std::vector<Eigen::Vector3f> particles;
  for (int i = 0; i < 20; ++i)
    for (int j = 0; j < 20; ++j)
      for (int k = 0; k < 20; ++k) particles.emplace_back(0.5f * i, 0.5f * j, 0.5f * k);
  LevelSet ls = buildMetaballLevelSet(particles, params);
  ASSERT_FLOAT_EQ(ls.sample(Eigen::Vector3f(3.0f, 4.75f, 4.75f)), -params.halfWidth * params.voxelSize);
  intersectWithBox(ls, Eigen::Vector3f(3.1f, 1.0f, 1.0f), Eigen::Vector3f(8.0f, 8.0f, 8.0f));
  for (const float x : {2.5f, 2.75f, 3.0f, 3.25f, 3.5f, 3.75f})
    EXPECT_NEAR(ls.sample(Eigen::Vector3f(x, 4.75f, 4.75f)), 3.1f - x, 1e-5f) << "x " << x;
  const float background = params.halfWidth * params.voxelSize;
  EXPECT_FLOAT_EQ(ls.sample(Eigen::Vector3f(5.5f, 4.75f, 4.75f)), -background);  // still inside
  EXPECT_FLOAT_EQ(ls.sample(Eigen::Vector3f(1.5f, 4.75f, 4.75f)), background);   // cut away
  EXPECT_FLOAT_EQ(ls.sample(Eigen::Vector3f(4.75f, 4.75f, 0.0f)), background);
}

TEST(ClipToBox, SameGridForOneAndTwoThreads) {
  const MetaballParams params = metaball(0.4f, 0.6f, 1.0f, 0.1f);
  const std::vector<Eigen::Vector3f> particles = randomCluster(3000, 1.5f, 13);
  const auto build = [&](int threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(threads));
    LevelSet ls = buildMetaballLevelSet(particles, params);
    intersectWithBox(ls, Eigen::Vector3f(-1.0f, -1.2f, -0.8f), Eigen::Vector3f(1.1f, 0.9f, 1.3f));
    return ls;
  };
  const LevelSet one = build(1);
  const LevelSet two = build(2);
  EXPECT_EQ(one.activeVoxelCount(), two.activeVoxelCount());
  const Eigen::Vector3f lo = Eigen::Vector3f::Constant(-2.0f), hi = Eigen::Vector3f::Constant(2.0f);
  EXPECT_EQ(sampleVoxelCentres(one, lo, hi), sampleVoxelCentres(two, lo, hi));
}

TEST(ClipToBox, EmptyStaysEmptyAndABoxInsideOutThrows) {
  LevelSet empty = buildMetaballLevelSet({}, kParamsA);
  intersectWithBox(empty, Eigen::Vector3f::Zero(), Eigen::Vector3f::Ones());
  EXPECT_TRUE(empty.empty());
  LevelSet blob = buildMetaballLevelSet({Eigen::Vector3f::Zero()}, kParamsA);
  intersectWithBox(blob, Eigen::Vector3f::Constant(5.0f), Eigen::Vector3f::Constant(6.0f));  // misses it
  EXPECT_TRUE(blob.empty());
  EXPECT_GT(blob.sample(Eigen::Vector3f::Zero()), 0.0f);
  EXPECT_THROW(intersectWithBox(blob, Eigen::Vector3f(1, 0, 0), Eigen::Vector3f(0, 1, 1)), std::invalid_argument);
}

// A tank: fluid particles on the fluid-block lattice (the first half a spacing inside the walls)
// filling the container [0, 12] x [0, 8] x [0, 6] up to z = 4, surfaced as the surface stage does.
struct TankFrame {
  pipeline::Scene scene;
  pipeline::ParticleFrame frame;
  TankFrame() {
    scene.sim.container.min = Eigen::Vector3f(0, 0, 0);
    scene.sim.container.max = Eigen::Vector3f(12, 8, 6);
    scene.surface.fluid = metaball(2.0f, 0.5f, 1.0f, 0.25f);
    for (int i = 0; i < 12; ++i)
      for (int j = 0; j < 8; ++j)
        for (int k = 0; k < 4; ++k) {
          frame.px.push_back(0.5f + float(i));
          frame.py.push_back(0.5f + float(j));
          frame.pz.push_back(0.5f + float(k));
          frame.kind.push_back(0);
        }
  }
};

TEST(ClipToBox, TankFluidMeshLiesInsideTheContainer) {
  TankFrame tank;
  const float h = tank.scene.surface.fluid.voxelSize;
  const Eigen::Vector3f lo = tank.scene.sim.container.min, hi = tank.scene.sim.container.max;
  const auto outside = [&](const TriangleMesh& mesh) {  // farthest a vertex lies outside the container
    float worst = 0.0f;
    for (const Eigen::Vector3f& p : mesh.positions) worst = std::max(worst, (lo - p).cwiseMax(p - hi).maxCoeff());
    return worst;
  };
  tank.scene.surface.clipToContainer = false;
  const TriangleMesh unclipped = meshLevelSet(pipeline::surfaceFrame(tank.scene, tank.frame).at("fluid"));
  EXPECT_GT(outside(unclipped), 0.5f);  // the metaball field alone reaches past the walls
  tank.scene.surface.clipToContainer = true;
  const LevelSet clipped = std::move(pipeline::surfaceFrame(tank.scene, tank.frame).at("fluid"));
  const TriangleMesh mesh = meshLevelSet(clipped);
  ASSERT_GT(mesh.triangles.size(), 1000u);
  EXPECT_LE(outside(mesh), 0.5f * h);
  // Still the tank's water: inside at the walls' feet, the free surface above the top layer.
  EXPECT_LT(clipped.sample(Eigen::Vector3f(0.1f, 0.1f, 0.1f)), 0.0f);
  EXPECT_LT(clipped.sample(Eigen::Vector3f(6.0f, 4.0f, 4.0f)), 0.0f);
  EXPECT_GT(clipped.sample(Eigen::Vector3f(6.0f, 4.0f, 5.5f)), 0.0f);
}

// A square sheet of (2 m + 1)^2 particles `spacing` apart in the plane through `centre` spanned by
// u and v; the centre particle is index (2 m + 1) * m + m.
std::vector<Eigen::Vector3f> sheet(int m, float spacing, const Eigen::Vector3f& centre, const Eigen::Vector3f& u,
                                   const Eigen::Vector3f& v) {
  std::vector<Eigen::Vector3f> out;
  for (int i = -m; i <= m; ++i)
    for (int j = -m; j <= m; ++j) out.push_back(centre + spacing * (float(i) * u + float(j) * v));
  return out;
}

TEST(AnisotropicKernels, SheetFlattensAcrossItsNormalByTheMaximumStretch) {
  const Eigen::Vector3f n = Eigen::Vector3f(1, 2, 3).normalized();
  const Eigen::Vector3f u = n.unitOrthogonal(), v = n.cross(u);
  // Spacing 0.2 < R / k_r, so that k_r, not the spacing, sets the thinnest axis.
  const std::vector<Eigen::Vector3f> points = sheet(6, 0.2f, {1, 2, 3}, u, v);
  AnisotropyParams params;
  params.maxStretch = 4.0f;
  const float radius = 1.0f;
  const std::vector<EllipsoidKernel> kernels = anisotropicKernels(points, radius, params);
  ASSERT_EQ(kernels.size(), points.size());
  const EllipsoidKernel& k = kernels[13 * 6 + 6];
  // In the plane the radius is R; across it R / k_r (the variance across a plane is 0).
  EXPECT_NEAR(n.dot(k.shape * n), 16.0f, 1e-3f);
  EXPECT_NEAR(u.dot(k.shape * u), 1.0f, 1e-3f);
  EXPECT_NEAR(v.dot(k.shape * v), 1.0f, 1e-3f);
  EXPECT_NEAR(u.dot(k.shape * v), 0.0f, 1e-3f);
  EXPECT_EQ(k.centre, points[13 * 6 + 6]);  // smoothing 0: the particle's own position
}

TEST(AnisotropicKernels, LatticeBulkIsASphereAndALoneParticleToo) {
  std::vector<Eigen::Vector3f> points;
  for (int i = -3; i <= 3; ++i)
    for (int j = -3; j <= 3; ++j)
      for (int k = -3; k <= 3; ++k) points.emplace_back(0.5f * i, 0.5f * j, 0.5f * k);
  points.emplace_back(20.0f, 0.0f, 0.0f);  // alone
  const float radius = 1.2f;
  const std::vector<EllipsoidKernel> kernels = anisotropicKernels(points, radius, AnisotropyParams{});
  const Eigen::Matrix3f sphere = Eigen::Matrix3f::Identity() / (radius * radius);
  EXPECT_LT((kernels[(7 * 7 * 7 - 1) / 2].shape - sphere).norm(), 1e-4f);  // the centre (cubic symmetry)
  EXPECT_EQ(kernels.back().shape, sphere);
  // A particle on a face of the block is flattened across the face, never stretched past R.
  const Eigen::Matrix3f& face = kernels[3 * 49 + 3 * 7 + 6].shape;  // (0, 0, 1.5): the top face
  EXPECT_GT(face(2, 2), 1.5f / (radius * radius));
  EXPECT_NEAR(face(0, 0), 1.0f / (radius * radius), 0.05f);
}

TEST(AnisotropicKernels, SmoothingMovesTheCentreToTheWeightedMean) {
  const std::vector<Eigen::Vector3f> points = sheet(3, 0.5f, {0, 0, 0}, {1, 0, 0}, {0, 1, 0});
  AnisotropyParams params;
  params.smoothing = 1.0f;
  const std::vector<EllipsoidKernel> kernels = anisotropicKernels(points, 1.0f, params);
  // A corner particle's neighbours lie towards +x and +y; the mean is inside the sheet.
  EXPECT_GT(kernels[0].centre.x(), points[0].x() + 0.1f);
  EXPECT_GT(kernels[0].centre.y(), points[0].y() + 0.1f);
  EXPECT_NEAR(kernels[0].centre.z(), 0.0f, 1e-6f);
  EXPECT_NEAR((kernels[24].centre - points[24]).norm(), 0.0f, 1e-6f);  // the centre: symmetric
  params.smoothing = 1.5f;
  EXPECT_THROW(anisotropicKernels(points, 1.0f, params), std::invalid_argument);
}

TEST(AnisotropicKernels, SameGridForOneAndTwoThreads) {
  MetaballParams params = metaball(0.4f, 0.6f, 1.0f, 0.1f);
  params.kernel = MetaballKernel::Anisotropic;
  params.anisotropy.smoothing = 0.5f;
  const std::vector<Eigen::Vector3f> particles = randomCluster(3000, 1.5f, 11);
  const auto build = [&](int threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(threads));
    return buildMetaballLevelSet(particles, params);
  };
  const LevelSet one = build(1);
  const LevelSet two = build(2);
  EXPECT_EQ(one.activeVoxelCount(), two.activeVoxelCount());
  const Eigen::Vector3f lo = Eigen::Vector3f::Constant(-2.0f), hi = Eigen::Vector3f::Constant(2.0f);
  EXPECT_EQ(sampleVoxelCentres(one, lo, hi), sampleVoxelCentres(two, lo, hi));
}

TEST(AnisotropicKernels, SheetSurfaceIsThinAndDoesNotDependOnTheSheetsOrientation) {
  // A sheet one particle thick: its kernels are flattened to R / 4 across it, so its surface lies
  // where 16 pi R^2 / 3 (1 - 16 z^2 / R^2)^3 = T (the sum over the sheet, 16 particles per m^2),
  // z = 0.21 R here, on both sides and for any orientation of the sheet against the grid.
  MetaballParams params = metaball(1.0f, 0.5f, 1.0f, 0.05f);
  params.kernel = MetaballKernel::Anisotropic;
  const Eigen::Vector3f centre(0.3f, -0.2f, 0.1f);
  double reference = -1.0;
  for (const Eigen::Vector3f& n : {Eigen::Vector3f(0, 0, 1), Eigen::Vector3f(1, 1, 1).normalized()}) {
    const Eigen::Vector3f u = n.unitOrthogonal(), v = n.cross(u);
    const LevelSet ls = buildMetaballLevelSet(sheet(8, 0.25f, centre, u, v), params);
    const double d = zeroCrossing(ls, centre, n, 1.0f);
    EXPECT_NEAR(zeroCrossing(ls, centre, -n, 1.0f), d, 0.5 * params.voxelSize);
    EXPECT_NEAR(d, 0.2075 * params.radius, 0.5 * params.voxelSize) << "normal " << n.transpose();
    if (reference < 0.0) reference = d;
    EXPECT_NEAR(d, reference, 0.5 * params.voxelSize) << "normal " << n.transpose();
  }
}

TEST(AnisotropicKernels, NoAxisIsThinnerThanTheSpacingToTheNearestNeighbour) {
  // A sheet 1 m apart, R = 2 m, k_r = 4: the variances flatten it to R / 4 = 0.5 m across, the
  // nearest neighbour keeps that axis at 1 m; in the plane the radius stays R.
  const Eigen::Vector3f n = Eigen::Vector3f(1, 2, 3).normalized();
  const Eigen::Vector3f u = n.unitOrthogonal(), v = n.cross(u);
  const std::vector<Eigen::Vector3f> points = sheet(6, 1.0f, {1, 2, 3}, u, v);
  AnisotropyParams params;
  params.neighbourRadius = 1.5f;
  const EllipsoidKernel& k = anisotropicKernels(points, 2.0f, params)[13 * 6 + 6];
  EXPECT_NEAR(n.dot(k.shape * n), 1.0f, 1e-3f);
  EXPECT_NEAR(u.dot(k.shape * u), 0.25f, 1e-3f);
}

// Two layers of particles `spacing` apart across (z), each a square lattice `stretch` spacings
// apart in x and y: a shell wall (the jellyfish's bell is two layers, the membrane three) whose
// sheet has been stretched.
std::vector<Eigen::Vector3f> stretchedWall(float spacing, float stretch) {
  std::vector<Eigen::Vector3f> out;
  for (int layer = 0; layer < 2; ++layer)
    for (int i = -8; i <= 8; ++i)
      for (int j = -8; j <= 8; ++j) out.emplace_back(spacing * stretch * float(i), spacing * stretch * float(j), spacing * float(layer));
  return out;
}

TEST(ThinBodies, StretchedTwoLayerWallIsOneSlabWithNoSlitBetweenItsLayers) {
  // The jellyfish's body surface (scenes/jellyfish.json: R = 0.9 m, T = 0.5, anisotropic kernels,
  // spacing 0.5 m) on a wall of its two layers, at rest and stretched in its plane as the bell is
  // where it bulges: down the normal through the wall, on a particle's line and between the
  // lattice's particles, the level set is inside from half a spacing below the lower layer to half a
  // spacing above the upper one, with no slit of outside between the layers.
  const pipeline::Scene scene = pipeline::loadScene(std::string(KURAGE_SOURCE_DIR) + "/scenes/jellyfish.json");
  const MetaballParams params = scene.surface.bodies;
  ASSERT_EQ(params.kernel, MetaballKernel::Anisotropic);
  const float spacing = scene.sim.bodies.at(0).spacingMetres(scene.sim.fluid.spacing);
  ASSERT_FLOAT_EQ(spacing, 0.5f);
  for (const float stretch : {1.0f, 1.2f, 1.4f}) {
    const LevelSet ls = buildMetaballLevelSet(stretchedWall(spacing, stretch), params);
    for (const float offset : {0.0f, 0.5f}) {
      const float x = offset * spacing * stretch + 0.01f, y = offset * spacing * stretch - 0.02f;
      float outside = -1.0f;  // the height of the first point found outside, if any
      for (float z = -0.25f * spacing; z <= 1.25f * spacing; z += 0.25f * params.voxelSize)
        if (outside < -0.5f && ls.sample(Eigen::Vector3f(x, y, z)) >= 0.0f) outside = z;
      EXPECT_LT(outside, -0.5f) << "stretch " << stretch << ", at (" << x << ", " << y << "): outside at z = " << outside;
    }
  }
}

// Appends a particle at rest to a cache frame, with its kind and rest density factor.
void addParticle(pipeline::ParticleFrame& frame, const Eigen::Vector3f& p, int kind, float restDensityFactor) {
  frame.px.push_back(p.x()), frame.py.push_back(p.y()), frame.pz.push_back(p.z());
  for (auto* v : {&frame.vx, &frame.vy, &frame.vz}) v->push_back(0.0f);
  frame.id.push_back(int64_t(frame.id.size()));
  frame.kind.push_back(kind);
  frame.restDensityFactor.push_back(restDensityFactor);
}

TEST(ThinBodies, StretchedMembraneOfRoundBlobsHasNoHole) {
  // The membrane's body surface (scenes/membrane.json: R = 0.9 m, T = 0.5, round blobs, spacing
  // 0.5 m, 3 layers), its sheet stretched in its plane by s (layers kept 0.5 m apart) with the
  // telescopic density of that stretch, rest density / s^2 (the area each particle stands for):
  // at every point between the lattice's particles, the normal through the sheet meets its inside.
  // Surfaced as the pipeline does (pipeline::surfaceFrame). Without the stretch scales, blobs of
  // radius R leave a hole in each lattice square from s = 2.2 (spacing 1.1 m).
  pipeline::Scene scene = pipeline::loadScene(std::string(KURAGE_SOURCE_DIR) + "/scenes/membrane.json");
  ASSERT_EQ(scene.surface.bodies.kernel, MetaballKernel::Isotropic);
  scene.surface.clipToContainer = false;
  const float spacing = scene.sim.bodies.at(0).spacingMetres(scene.sim.fluid.spacing);
  ASSERT_FLOAT_EQ(spacing, 0.5f);
  for (const float stretch : {1.0f, 2.4f}) {
    pipeline::ParticleFrame frame;
    frame.kindNames = pipeline::kindNames(scene);
    const int n = 8;
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j)
        for (int k = 0; k < 3; ++k) {
          addParticle(frame, {stretch * spacing * float(i), stretch * spacing * float(j), spacing * float(k)}, 1,
                      1.0f / (stretch * stretch));
        }
    const auto surfaces = pipeline::surfaceFrame(scene, frame);
    const LevelSet& sheet = surfaces.at(scene.sim.bodies.at(0).name);
    size_t holes = 0, probed = 0;
    for (int i = 2; i < n - 3; ++i)
      for (int j = 2; j < n - 3; ++j)
        for (const float offset : {0.25f, 0.5f}) {
          const float x = stretch * spacing * (float(i) + offset), y = stretch * spacing * (float(j) + 0.5f);
          bool inside = false;
          for (float z = -spacing; z <= 3.0f * spacing && !inside; z += 0.25f * scene.surface.bodies.voxelSize)
            inside = sheet.sample(Eigen::Vector3f(x, y, z)) < 0.0f;
          holes += !inside;
          ++probed;
        }
    EXPECT_EQ(holes, 0u) << "stretch " << stretch << ": " << holes << " of " << probed << " normals miss the sheet";
  }
}

TEST(ThinBodies, AMembraneAgainstAWallHidesTheFluidBehindIt) {
  // scenes/membrane.json's surfaces: its sheet (two layers, 0.5 m spacing) pressed on the tank's
  // front wall (y = 0) by the fluid behind it (0.9 m from the wall). The fluid's blobs (R 1.6 m)
  // reach through the sheet to the wall; both surfaces are clipped to the container, and the
  // sheet's face must be the outer one over the whole patch, or the camera in front sees the
  // water's face where the sheet should be.
  pipeline::Scene scene = pipeline::loadScene(std::string(KURAGE_SOURCE_DIR) + "/scenes/membrane.json");
  ASSERT_TRUE(scene.surface.clipToContainer);
  ASSERT_FLOAT_EQ(scene.sim.container.min.y(), 0.0f);
  pipeline::ParticleFrame frame;
  frame.kindNames = pipeline::kindNames(scene);
  for (int i = 0; i <= 12; ++i)
    for (int k = 0; k <= 12; ++k)
      for (const float y : {0.05f, 0.55f}) addParticle(frame, {0.5f * float(i), y, 10.0f + 0.5f * float(k)}, 1, 1.0f);
  for (int i = 0; i <= 6; ++i)
    for (int k = 0; k <= 6; ++k) addParticle(frame, {float(i), 0.9f, 10.0f + float(k)}, 0, 1.0f);
  const auto surfaces = pipeline::surfaceFrame(scene, frame);
  const LevelSet& fluid = surfaces.at("fluid");
  const LevelSet& sheet = surfaces.at(scene.sim.bodies.at(0).name);
  size_t fluidInFront = 0, fluidAtTheWall = 0, probed = 0;
  for (float x = 1.0f; x <= 5.0f; x += 0.25f)
    for (float z = 11.0f; z <= 15.0f; z += 0.25f) {
      // March from in front of the wall into the tank: which surface is met first.
      float sheetAt = 1.0f, fluidAt = 1.0f;
      for (float y = -0.5f; y <= 0.5f; y += 0.005f) {
        if (sheetAt > 0.9f && sheet.sample(Eigen::Vector3f(x, y, z)) < 0.0f) sheetAt = y;
        if (fluidAt > 0.9f && fluid.sample(Eigen::Vector3f(x, y, z)) < 0.0f) fluidAt = y;
      }
      fluidAtTheWall += fluidAt < 0.05f;
      fluidInFront += fluidAt <= sheetAt;
      ++probed;
    }
  EXPECT_GT(fluidAtTheWall, probed / 2) << "the fluid's surface should reach the wall through the sheet";
  EXPECT_EQ(fluidInFront, 0u) << fluidInFront << " of " << probed << " points show the fluid's face in front";
}

// The zero crossing along the line from `from` in direction `direction` (unit), first from
// outside to inside; -1 when there is none within maxT. Steps of a quarter voxel, then bisection.
double firstCrossing(const LevelSet& ls, const Eigen::Vector3f& from, const Eigen::Vector3f& direction, float maxT,
                     bool intoInside) {
  const float step = ls.voxelSize() * 0.25f;
  const auto wanted = [&](float t) { return (ls.sample(from + t * direction) < 0.0f) == intoInside; };
  if (wanted(0.0f)) return 0.0;
  for (float t = step; t <= maxT; t += step) {
    if (!wanted(t)) continue;
    float lo = t - step, hi = t;
    for (int i = 0; i < 40; ++i) {
      const float mid = 0.5f * (lo + hi);
      (wanted(mid) ? hi : lo) = mid;
    }
    return 0.5 * double(lo + hi);
  }
  return -1.0;
}

// The jellyfish's bell at rest: its particles as the simulation builds them, surfaced with the
// scene's own body settings (scenes/jellyfish.json).
struct RestBell {
  pipeline::Scene scene = pipeline::loadScene(std::string(KURAGE_SOURCE_DIR) + "/scenes/jellyfish.json");
  sim::BodyParams body = scene.sim.bodies.at(0);
  float spacing = body.spacingMetres(scene.sim.fluid.spacing);
  float inner = body.innerRadius;
  float outer = body.innerRadius + float(body.layers - 1) * spacing;
  std::vector<Eigen::Vector3f> points = sim::bodyPoints(body, scene.sim.fluid.spacing).positions;
};

// Along the ray from the bell's centre at polar angle `polar` (radians from the axis): where it
// enters the wall (from the cavity) and leaves it, metres from the centre.
std::pair<double, double> wallCrossings(const LevelSet& ls, const RestBell& bell, double polar) {
  const Eigen::Vector3f axis = bell.body.axis.normalized();
  const Eigen::Vector3f side = axis.unitOrthogonal();
  const Eigen::Vector3f d = (float(std::cos(polar)) * axis + float(std::sin(polar)) * side).normalized();
  const double in = firstCrossing(ls, bell.body.center, d, 2.0f * bell.outer, true);
  const float step = 0.25f * ls.voxelSize();  // from just inside the wall
  const double out =
      in < 0.0 ? -1.0 : in + step + firstCrossing(ls, bell.body.center + (float(in) + step) * d, d, 2.0f * bell.outer, false);
  return {in, out};
}

TEST(ThinBodies, RestBellHasAnOpenCavityAndAWallOfTheBuiltThickness) {
  const RestBell bell;
  ASSERT_EQ(bell.body.shape, sim::BodyShape::Shell);
  ASSERT_EQ(bell.scene.surface.bodies.kernel, MetaballKernel::Anisotropic);
  // Through the surface stage's own path (kind 1 is the first body, the bell; clipped to the tank).
  pipeline::ParticleFrame frame;
  for (const Eigen::Vector3f& p : bell.points) {
    frame.px.push_back(p.x()), frame.py.push_back(p.y()), frame.pz.push_back(p.z());
    frame.kind.push_back(1);
  }
  const LevelSet ls = std::move(pipeline::surfaceFrame(bell.scene, frame).at(bell.body.name));
  const float h = ls.voxelSize();
  // The built wall: from half a spacing inside the inner layer to half a spacing outside the
  // outer one (each layer stands for a slab one spacing thick).
  const double builtInner = bell.inner - 0.5 * bell.spacing, builtOuter = bell.outer + 0.5 * bell.spacing;
  const double built = builtOuter - builtInner;
  // Up the axis from below the bell: through the opening (nothing in the way from far below the
  // margin up to the cavity), into the wall near the apex.
  const Eigen::Vector3f axis = bell.body.axis.normalized();
  const Eigen::Vector3f below = bell.body.center - 2.0f * bell.outer * axis;
  const double entry = firstCrossing(ls, below, axis, 4.0f * bell.outer, true) - 2.0 * bell.outer;
  EXPECT_NEAR(entry, builtInner, h) << "the cavity's roof, metres above the bell's centre";
  const auto [in, out] = wallCrossings(ls, bell, 0.0);
  EXPECT_NEAR(in, entry, 1e-3);
  EXPECT_NEAR(out - in, built, 0.3 * built) << "wall thickness at the apex";
  // The same on the flank, between apex and margin.
  for (const double degrees : {20.0, 40.0, 60.0}) {
    const auto [a, b] = wallCrossings(ls, bell, degrees * M_PI / 180.0);
    EXPECT_NEAR(a, builtInner, 2.0 * h) << degrees << " degrees";
    EXPECT_NEAR(b - a, built, 0.3 * built) << degrees << " degrees";
  }
}

TEST(ThinBodies, IsotropicBlobsMakeTheBellWallTooThick) {
  // Why the jellyfish uses anisotropic kernels: the spheres' surface, at the same radius and
  // threshold, is far thicker than the built wall (and the test above would fail with it).
  const RestBell bell;
  MetaballParams params = bell.scene.surface.bodies;
  params.kernel = MetaballKernel::Isotropic;
  const auto [in, out] = wallCrossings(buildMetaballLevelSet(bell.points, params), bell, 0.0);
  const double built = bell.outer - bell.inner + bell.spacing;
  EXPECT_GT(out - in, 1.3 * built);
}

// Still water: a lattice of fluid particles (spacing 1 m, first half a spacing in) filling a box
// 16 x 16 x 6 m, each moved by up to +-`jitter` spacings (a settled fluid is not a perfect lattice).
std::vector<Eigen::Vector3f> stillWater(float jitter, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-jitter, jitter);
  std::vector<Eigen::Vector3f> out;
  for (int i = 0; i < 16; ++i)
    for (int j = 0; j < 16; ++j)
      for (int k = 0; k < 6; ++k) out.emplace_back(0.5f + float(i) + u(rng), 0.5f + float(j) + u(rng), 0.5f + float(k) + u(rng));
  return out;
}

// Max - min height of the free surface (the level set's zero crossing down vertical lines) over
// a grid of (x, y) at least 3 m from the sides.
double surfaceRoughness(const LevelSet& ls) {
  double lo = 1e9, hi = -1e9;
  for (float x = 3.0f; x <= 13.0f; x += 0.37f)
    for (float y = 3.0f; y <= 13.0f; y += 0.41f) {
      const double depth = firstCrossing(ls, Eigen::Vector3f(x, y, 10.0f), Eigen::Vector3f(0, 0, -1), 8.0f, true);
      EXPECT_GT(depth, 0.0);
      lo = std::min(lo, 10.0 - depth);
      hi = std::max(hi, 10.0 - depth);
    }
  return hi - lo;
}

TEST(ThinBodies, StillWaterSurfaceIsFlatToAQuarterSpacing) {
  // The jellyfish scene's fluid field (R = 2 m, T = 0.5: 2 spacings of this test's 1 m lattice)
  // with anisotropic kernels smoothed as Yu & Turk do (neighbourhood 1.5 R = 3 m, lambda = 0.9)
  // on still water: a lattice,
  // and the lattice with every particle moved by up to +-0.1 and +-0.2 spacings. The spheres'
  // surface follows the highest particles (0.33 m of lumps at +-0.2); the ellipsoids do not.
  const pipeline::Scene scene = pipeline::loadScene(std::string(KURAGE_SOURCE_DIR) + "/scenes/jellyfish.json");
  MetaballParams params = scene.surface.fluid;
  params.anisotropy.neighbourRadius = 1.5f;
  params.anisotropy.smoothing = 0.9f;
  const float spacing = 1.0f;  // stillWater's lattice
  ASSERT_EQ(params.radius, 2.0f);
  for (const float jitter : {0.0f, 0.1f, 0.2f}) {
    const std::vector<Eigen::Vector3f> water = stillWater(jitter, 5);
    params.kernel = MetaballKernel::Anisotropic;
    const LevelSet ls = buildMetaballLevelSet(water, params);
    const double anisotropic = surfaceRoughness(ls);
    EXPECT_LE(anisotropic, 0.25 * spacing) << "jitter " << jitter;
    // Where the surface lies: near the top layer of particles (5.5 m), not a metaball radius above.
    const double top = 10.0 - firstCrossing(ls, Eigen::Vector3f(8.1f, 8.1f, 10.0f), Eigen::Vector3f(0, 0, -1), 8.0f, true);
    EXPECT_NEAR(top, 5.5, 0.5 * spacing) << "jitter " << jitter;
    params.kernel = MetaballKernel::Isotropic;
    const double isotropic = surfaceRoughness(buildMetaballLevelSet(water, params));
    if (jitter == 0.2f) {
      EXPECT_GT(isotropic, 0.25 * spacing);  // the test can tell lumps
    }
  }
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
