// Renderer checks with answers derived by hand, needing no reference image.
//
// Furnace tests (pbrt-v4's integrators_test, Mitsuba's): inside a uniform environment of
// radiance 1, with no other light,
//   - a convex diffuse sphere of albedo rho renders as exactly rho (one bounce, then it sees the
//     environment in every direction);
//   - a mirror sphere of reflectance rho renders as rho;
//   - a clear dielectric sphere renders as 1: Fresnel reflection and transmission add up to one
//     at every interface, and every path eventually leaves;
//   - a translucent sphere of tint rho and IOR 1 (no Fresnel reflection) renders as rho^2: the
//     light is scattered diffusely into the sphere and again out of it;
//   - the checker ground shows each square's albedo.
// The diffuse, mirror and translucent cases have zero variance (every path has the same weight)
// with BSDF sampling alone, so these tests turn environment sampling off (with the sky sampled
// as a light and MIS the estimate is unbiased but noisy: test_integrators.cpp checks it);
// the dielectric case loses only paths that stay inside for more than max_depth bounces (at
// most F^63 with F < 0.2 here), so they are held to 1e-4. An absorbing dielectric sphere seen
// through its centre is checked against the geometric series of internal reflections.
//
// Refraction: a glass slab of thickness d over a checker ground shifts the ground seen through
// it by d (tan(theta_i) - tan(theta_t)) with sin(theta_i) = n sin(theta_t) (Snell).
#include "furnace_scene.h"
#include "render/renderer.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <numbers>
#include <string>

namespace kr = kurage::render;
using Eigen::Vector3f;

namespace {

constexpr float kPi = std::numbers::pi_v<float>;

kr::RenderScene furnace() { return kurage::test::furnaceScene(35.0f); }

struct FurnaceCase {
  const char* name;
  kr::Material material;
  Vector3f expected;
  float tolerance;  // per pixel
};

std::ostream& operator<<(std::ostream& os, const FurnaceCase& c) { return os << c.name; }

kr::Material makeMaterial(kr::MaterialType type, Vector3f albedo, float ior = 1.33f) {
  kr::Material m;
  m.type = type;
  m.albedo = albedo;
  m.ior = ior;
  return m;
}

const FurnaceCase kFurnaceCases[] = {
    {"Diffuse", makeMaterial(kr::MaterialType::Diffuse, {0.2f, 0.5f, 0.8f}), {0.2f, 0.5f, 0.8f}, 1e-5f},
    {"Mirror", makeMaterial(kr::MaterialType::Mirror, {0.9f, 0.6f, 0.3f}), {0.9f, 0.6f, 0.3f}, 1e-5f},
    {"Water", makeMaterial(kr::MaterialType::Dielectric, {1, 1, 1}, 1.33f), {1, 1, 1}, 1e-4f},
    {"Glass", makeMaterial(kr::MaterialType::Dielectric, {1, 1, 1}, 1.5f), {1, 1, 1}, 1e-4f},
    {"TranslucentWithoutFresnel", makeMaterial(kr::MaterialType::Translucent, {0.8f, 0.6f, 0.4f}, 1.0f),
     {0.64f, 0.36f, 0.16f}, 1e-5f},
};

class Furnace : public ::testing::TestWithParam<FurnaceCase> {};

}  // namespace

TEST_P(Furnace, ConvexSphereRendersAsDerived) {
  const FurnaceCase& c = GetParam();
  kr::RenderScene scene = furnace();
  scene.spheres.push_back({{{0, 0, 0}}, {}, 1.0f, c.material});
  kr::RenderSettings settings;
  settings.environmentSampling = false;  // zero-variance furnace (see the file's comment)
  settings.width = 24;
  settings.height = 24;
  settings.samplesPerPixel = 16;
  settings.maxDepth = 64;
  const kr::Image image = kr::renderFrame(scene, settings);
  // Pixels whose whole footprint lies inside the sphere's outline (radius 0.8 of it, to stay
  // clear of the edge): at distance 4 the outline has angular radius asin(1/4).
  const float tanHalf = std::tan(0.5f * scene.camera.verticalFovDegrees * kPi / 180.0f);
  const float outline = std::tan(std::asin(0.25f)) / tanHalf * 12.0f;  // pixels
  int inside = 0;
  for (int y = 0; y < 24; ++y)
    for (int x = 0; x < 24; ++x) {
      const float dx = x + 0.5f - 12.0f, dy = y + 0.5f - 12.0f;
      if (std::sqrt(dx * dx + dy * dy) > 0.8f * outline) continue;
      ++inside;
      const Vector3f v = image.at(x, y).head<3>();
      ASSERT_LT((v - c.expected).cwiseAbs().maxCoeff(), c.tolerance)
          << c.name << " pixel " << x << "," << y << ": " << v.transpose();
    }
  EXPECT_GT(inside, 100);
}

INSTANTIATE_TEST_SUITE_P(Materials, Furnace, ::testing::ValuesIn(kFurnaceCases),
                         [](const auto& info) { return std::string(info.param.name); });

TEST(FurnaceGround, CheckerSquaresShowTheirAlbedo) {
  kr::RenderScene scene = furnace();
  scene.ground.enabled = true;
  scene.ground.checkerSize = 1.0f;
  scene.ground.albedoA = {0.7f, 0.7f, 0.7f};
  scene.ground.albedoB = {0.2f, 0.3f, 0.4f};
  scene.camera.position = {0.3f, 0.2f, 6};
  scene.camera.lookAt = {0.3f, 0.2f, 0};
  scene.camera.up = {0, 1, 0};
  kr::RenderSettings settings;
  settings.environmentSampling = false;  // zero-variance furnace (see the file's comment)
  settings.width = 40;
  settings.height = 40;
  settings.samplesPerPixel = 1;  // pixel centres only would not do: any sample lands in one square
  const kr::Image image = kr::renderFrame(scene, settings);
  int a = 0, b = 0;
  for (int y = 0; y < 40; ++y)
    for (int x = 0; x < 40; ++x) {
      const Vector3f v = image.at(x, y).head<3>();
      if ((v - scene.ground.albedoA).norm() < 1e-5f) ++a;
      else if ((v - scene.ground.albedoB).norm() < 1e-5f) ++b;
      else ADD_FAILURE() << "pixel " << x << "," << y << " is neither albedo: " << v.transpose();
    }
  EXPECT_GT(a, 200);
  EXPECT_GT(b, 200);
}

TEST(Absorption, DielectricSphereThroughItsCentreFollowsBeerLambert) {
  // Seen along a diameter (normal incidence everywhere): reflection F0 = ((n-1)/(n+1))^2 off the
  // front, plus transmission through the sphere with a = exp(-sigma 2R) per crossing and any
  // number of internal reflections, each path ending in the environment through the front or the
  // back: L = F0 + (1-F0)^2 sum_k a^(k+1) F0^k = F0 + (1-F0)^2 a / (1 - F0 a) (= 1 for a = 1).
  // Per path the value is 1 (reflected) or about a: standard deviation sqrt(F0 (1-F0)) (1-a)
  // = 0.12, so 4096 paths give 0.002; bound 0.01. Red, green and blue have sigma 0.5, 0.1, 0.
  kr::RenderScene scene = furnace();
  kr::Material m = makeMaterial(kr::MaterialType::Dielectric, {1, 1, 1}, 1.5f);
  m.absorption = {0.5f, 0.1f, 0.0f};
  scene.spheres.push_back({{{0, 0, 0}}, {}, 1.0f, m});
  scene.camera.verticalFovDegrees = 0.2f;  // the one pixel sees within 0.007 of the axis
  kr::RenderSettings settings;
  settings.environmentSampling = false;  // zero-variance furnace (see the file's comment)
  settings.width = 1;
  settings.height = 1;
  settings.samplesPerPixel = 4096;
  settings.maxDepth = 64;
  const Vector3f v = kr::renderFrame(scene, settings).at(0, 0).head<3>();
  const float f0 = (0.5f / 2.5f) * (0.5f / 2.5f);
  for (int c = 0; c < 3; ++c) {
    const float a = std::exp(-m.absorption[c] * 2.0f);
    const float expected = f0 + (1 - f0) * (1 - f0) * a / (1 - f0 * a);
    EXPECT_NEAR(v[c], expected, 0.01f) << "channel " << c;
  }
  EXPECT_LT(v.x(), 0.45f) << "absorption darkens red";
}

TEST(Refraction, GlassSlabShiftsTheCheckerboardBySnellsLaw) {
  // A camera looks down at 45 degrees (nearly parallel rays: 1 degree field of view) at a
  // checker ground with squares 1 m wide; a glass slab (n = 1.5, d = 2 m thick) floats over it.
  // Through the slab, the ground point seen along each pixel's ray moves towards the camera by
  // d (tan(theta_i) - tan(theta_t)); each pixel row must show the colour of the square Snell's
  // law predicts (rows within 0.05 m of a square's edge are skipped), and not the colour the
  // straight ray would give on at least a few rows (the test can fail).
  kr::TriangleMesh slab;
  const float lo = 0.5f, hi = 2.5f, s = 200.0f;
  slab.positions = {{-s, -s, lo}, {s, -s, lo}, {s, s, lo}, {-s, s, lo}, {-s, -s, hi}, {s, -s, hi}, {s, s, hi}, {-s, s, hi}};
  slab.triangles = {{0, 2, 1}, {0, 3, 2}, {4, 5, 6}, {4, 6, 7}, {0, 1, 5}, {0, 5, 4},
                    {1, 2, 6}, {1, 6, 5}, {2, 3, 7}, {2, 7, 6}, {3, 0, 4}, {3, 4, 7}};  // CCW from outside
  kr::RenderScene scene = furnace();
  scene.meshes.push_back({&slab, makeMaterial(kr::MaterialType::Dielectric, {1, 1, 1}, 1.5f)});
  scene.ground.enabled = true;
  scene.ground.checkerSize = 1.0f;
  scene.ground.albedoA = {0.9f, 0.9f, 0.9f};
  scene.ground.albedoB = {0.05f, 0.05f, 0.05f};
  scene.camera.position = {0.5f, -20.0f, 20.0f};
  scene.camera.lookAt = {0.5f, 0.0f, 0.0f};
  scene.camera.verticalFovDegrees = 14.0f;
  kr::RenderSettings settings;
  settings.environmentSampling = false;  // zero-variance furnace (see the file's comment)
  settings.width = 8;
  settings.height = 160;
  // Dark squares read about 0.15 (0.05 albedo plus ~10 % Fresnel reflection of the white
  // environment), bright ones about 0.8; a dark pixel reads above 0.45 only if a third of its
  // 64 paths reflect, whose binomial probability (p ~ 0.1) is below 1e-6.
  settings.samplesPerPixel = 64;
  settings.maxDepth = 16;
  const kr::Image image = kr::renderFrame(scene, settings);

  const Vector3f forward = (scene.camera.lookAt - scene.camera.position).normalized();
  const Vector3f right = forward.cross(scene.camera.up).normalized();
  const Vector3f up = right.cross(forward);
  const float tanHalf = std::tan(0.5f * scene.camera.verticalFovDegrees * kPi / 180.0f);
  const int x = settings.width / 2;
  int checked = 0, snellMatches = 0, straightMismatches = 0;
  for (int y = 0; y < settings.height; ++y) {
    const float py = (1.0f - 2.0f * (y + 0.5f) / settings.height) * tanHalf;
    const float px = (2.0f * (x + 0.5f) / settings.width - 1.0f) * tanHalf * settings.width / settings.height;
    const Vector3f d = (forward + px * right + py * up).normalized();
    // Straight ray to the ground, then Snell's shift inside the slab (horizontal, along d's
    // horizontal direction, back towards the camera).
    const Vector3f straight = scene.camera.position - scene.camera.position.z() / d.z() * d;
    const float sinI = std::sqrt(1.0f - d.z() * d.z());
    const float sinT = sinI / 1.5f;
    const float shift = (hi - lo) * (sinI / std::abs(d.z()) - sinT / std::sqrt(1.0f - sinT * sinT));
    const Vector3f horizontal = Vector3f(d.x(), d.y(), 0).normalized();
    const Vector3f seen = straight - shift * horizontal;
    const auto square = [](const Vector3f& p) { return (int(std::floor(p.x())) + int(std::floor(p.y()))) & 1; };
    const auto nearEdge = [](const Vector3f& p) {
      const float fy = p.y() - std::floor(p.y());
      return fy < 0.05f || fy > 0.95f;
    };
    if (nearEdge(seen)) continue;
    ++checked;
    const float value = image.at(x, y).x();
    const int shown = value > 0.45f ? 0 : 1;  // albedoA bright = even squares
    snellMatches += shown == square(seen);
    straightMismatches += !nearEdge(straight) && shown != square(straight);
  }
  EXPECT_GT(checked, 100);
  EXPECT_EQ(snellMatches, checked) << "rows whose colour Snell's law does not predict";
  EXPECT_GT(straightMismatches, 10) << "the slab should shift the pattern visibly";
}

TEST(FurnaceChecker, CheckerTexturedMeshShowsItsTwoAlbedos) {
  // A diffuse quad (a tank wall) with a 3-D checker of 1 m cells in the furnace: one bounce,
  // then the environment, so every pixel is exactly one of the two albedos, and both appear.
  kr::TriangleMesh wall;
  wall.positions = {{-3, 0.5f, -3}, {3, 0.5f, -3}, {3, 0.5f, 3}, {-3, 0.5f, 3}};
  wall.triangles = {{0, 1, 2}, {0, 2, 3}};
  kr::Material m = makeMaterial(kr::MaterialType::Diffuse, {0.7f, 0.7f, 0.7f});
  m.checkerSize = 1.0f;
  m.albedoB = {0.2f, 0.4f, 0.6f};
  kr::RenderScene scene = furnace();
  scene.meshes.push_back({&wall, m});
  kr::RenderSettings settings;
  settings.environmentSampling = false;  // zero-variance furnace (see the file's comment)
  settings.width = 32;
  settings.height = 32;
  settings.samplesPerPixel = 1;
  const kr::Image image = kr::renderFrame(scene, settings);
  int a = 0, b = 0;
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 32; ++x) {
      const Vector3f v = image.at(x, y).head<3>();
      if ((v - m.albedo).norm() < 1e-5f) ++a;
      else if ((v - m.albedoB).norm() < 1e-5f) ++b;
      else ADD_FAILURE() << "pixel " << x << "," << y << ": " << v.transpose();
    }
  EXPECT_GT(a, 200);
  EXPECT_GT(b, 200);
}
