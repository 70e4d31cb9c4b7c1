// Tracer tests with analytic answers: sky gradient, Lambert radiance under a sun, hard and soft
// shadows, a rectangular light's irradiance, smooth normals, clip plane, alpha, camera keys,
// thread-count independence, and tubes along B-splines (width, taper, ends, shading, shadow,
// clip plane, closedness, determinism), rays leaving a far or tilted ground not blocked by it,
// and the chains of a scene drawn as such tubes
// (pipeline/render_scene.h chainTubes, the render stage). The furnace and refraction checks are
// in test_render_validation.cpp.
#include "render/renderer.h"

#include "render/embree_scene.h"
#include "render/frame_scene.h"

#include "pipeline/io/files.h"
#include "pipeline/render_scene.h"
#include "pipeline/stages.h"
#include "test_util.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <numbers>

namespace kr = kurage::render;
using Eigen::Vector3f;

namespace {

constexpr float kPi = std::numbers::pi_v<float>;

// Pixel (column, row) whose footprint contains the image of world point p, for the perspective
// camera of camera.h (vertical FOV, look-at, row 0 on top).
Eigen::Vector2i project(const kr::Camera& camera, const kr::RenderSettings& s, const Vector3f& p) {
  const Vector3f forward = (camera.lookAt - camera.position).normalized();
  const Vector3f right = forward.cross(camera.up).normalized();
  const Vector3f up = right.cross(forward);
  const Vector3f d = p - camera.position;
  const float tanHalf = std::tan(0.5f * camera.verticalFovDegrees * kPi / 180.0f);
  const float aspect = static_cast<float>(s.width) / static_cast<float>(s.height);
  const float sx = d.dot(right) / d.dot(forward) / (aspect * tanHalf);  // [-1, 1] left to right
  const float sy = d.dot(up) / d.dot(forward) / tanHalf;               // [-1, 1] bottom to top
  return {static_cast<int>(std::floor((sx + 1.0f) * 0.5f * s.width)),
          static_cast<int>(std::floor((1.0f - sy) * 0.5f * s.height))};
}

// Point where the ray through the centre of pixel (x, y) meets the plane y = 0.
Vector3f pixelCentreOnPlaneY0(const kr::Camera& camera, const kr::RenderSettings& s, int x, int y) {
  const Vector3f forward = (camera.lookAt - camera.position).normalized();
  const Vector3f right = forward.cross(camera.up).normalized();
  const Vector3f up = right.cross(forward);
  const float tanHalf = std::tan(0.5f * camera.verticalFovDegrees * kPi / 180.0f);
  const float aspect = static_cast<float>(s.width) / static_cast<float>(s.height);
  const float px = (2.0f * (x + 0.5f) / s.width - 1.0f) * aspect * tanHalf;
  const float py = (1.0f - 2.0f * (y + 0.5f) / s.height) * tanHalf;
  const Vector3f dir = forward + px * right + py * up;
  return camera.position - camera.position.y() / dir.y() * dir;
}

Vector3f rgb(const kr::Image& image, int x, int y) { return image.at(x, y).head<3>(); }

// A triangle in the plane y = 0, large around the origin, seen from the camera below.
kr::TriangleMesh bigTriangle(float size) {
  kr::TriangleMesh mesh;
  mesh.positions = {{-size, 0, -size}, {size, 0, -size}, {0, 0, size}};
  mesh.triangles = {{0, 1, 2}};
  return mesh;
}

// No light at all: black environment, sun off, no ground.
kr::RenderScene darkScene() {
  kr::RenderScene scene;
  scene.environment.type = kr::EnvironmentType::Uniform;
  scene.environment.zenith = Vector3f::Zero();
  scene.sun.irradiance = Vector3f::Zero();
  scene.ground.enabled = false;
  scene.camera.position = {0, -5, 0};
  scene.camera.lookAt = {0, 0, 0};
  scene.camera.up = {0, 0, 1};
  scene.camera.verticalFovDegrees = 45.0f;
  return scene;
}

// A plain white Lambertian ground (albedo 1, no checker).
void addWhiteGround(kr::RenderScene& scene) {
  scene.ground.enabled = true;
  scene.ground.checkerSize = 0.0f;
  scene.ground.albedoA = {1, 1, 1};
}

// A sun of irradiance pi travelling along `direction`: a white Lambertian surface facing it
// reflects radiance 1.
void setSun(kr::RenderScene& scene, const Vector3f& direction, float angularDiameterDegrees) {
  scene.sun.direction = direction;
  scene.sun.irradiance = {kPi, kPi, kPi};
  scene.sun.angularDiameterDegrees = angularDiameterDegrees;
}

kr::RenderSettings renderSettings(int width, int height, int samplesPerPixel, int maxDepth) {
  kr::RenderSettings settings;
  settings.width = width;
  settings.height = height;
  settings.samplesPerPixel = samplesPerPixel;
  settings.maxDepth = maxDepth;
  return settings;
}

}  // namespace

TEST(Tracer, EmptySceneShowsSkyGradient) {
  kr::RenderScene scene;
  scene.camera.position = {0, 0, 1};
  scene.camera.lookAt = {0, 10, 1};  // horizontal
  scene.ground.enabled = false;
  kr::RenderSettings settings;
  settings.width = 24;
  settings.height = 32;
  settings.samplesPerPixel = 1;
  const kr::Image image = kr::renderFrame(scene, settings);
  ASSERT_EQ(image.width(), 24);
  ASSERT_EQ(image.height(), 32);
  const int cx = settings.width / 2;
  const auto toZenith = [&](int y) { return (rgb(image, cx, y) - scene.environment.zenith).norm(); };
  EXPECT_LT(toZenith(0), toZenith(settings.height - 1) - 0.1f);
  for (int y = 1; y < settings.height; ++y) EXPECT_LE(toZenith(y - 1), toZenith(y) + 1e-6f) << "row " << y;
  // Below the horizon the sky is the horizon colour; everything is opaque.
  EXPECT_LT((rgb(image, cx, settings.height - 1) - scene.environment.horizon).norm(), 1e-5f);
  EXPECT_EQ(image.at(0, 0)[3], 1.0f);
}

TEST(FrameScene, RaysLeavingTheGroundUpwardsAreNotBlockedByItAtAnyDistance) {
  // Points on a tilted ground from 30 m to 100 km from a camera 27 m above it: the point computed
  // as o + t d lies a rounding error above or below the plane (growing with the distance, as the
  // plane's normal is not an axis), so the ground seems to block rays that leave it from there;
  // from where leave() puts their origin it never does.
  kr::RenderScene scene;
  scene.ground.normal = Vector3f(0.3f, 0.1f, 1.0f);
  kr::EmbreeScene geometry;
  geometry.update(scene);
  const kr::EnvironmentSampler none;
  const kr::FrameScene frame(scene, geometry, none, false);
  const Vector3f n = scene.ground.normal.normalized();
  const Vector3f eye(10, -22, 27);
  kr::RayCounters counters;
  int blockedAtThePoint = 0, blockedAfterLeaving = 0;
  constexpr int kPoints = 2000;
  for (int i = 0; i < kPoints; ++i) {
    const float distance = 30.0f * std::pow(1e5f / 30.0f, float(i) / (kPoints - 1));
    const float phi = 0.37f * float(i);
    const Vector3f along(std::cos(phi), std::sin(phi), 0);
    const Vector3f onPlane = (along - along.dot(n) * n).normalized();
    const Vector3f target = (eye - eye.dot(n) * n) + distance * onPlane;
    const kr::Hit hit = frame.intersect(eye, (target - eye).normalized(), counters);
    ASSERT_EQ(hit.kind, kr::Hit::Ground) << i;
    const Vector3f across = Vector3f(std::cos(3.0f * phi), std::sin(3.0f * phi), 0);
    const Vector3f up = ((across - across.dot(n) * n).normalized() + (0.02f + 0.5f * float(i % 7)) * n).normalized();
    blockedAtThePoint += frame.groundBlocks(hit.point, up) ? 1 : 0;
    blockedAfterLeaving += frame.groundBlocks(frame.leave(hit, up), up) ? 1 : 0;
  }
  EXPECT_GT(blockedAtThePoint, kPoints / 10);  // the rounding this guards against is real
  EXPECT_EQ(blockedAfterLeaving, 0);
}

TEST(Tracer, SunLitTriangleHasAlbedoOverPiTimesIrradiance) {
  // Lambert: L = albedo / pi * E * cos. A point sun (0 degrees) is sampled exactly, and the
  // bounce ray escapes into a black environment, so there is no noise: tolerance 1e-5.
  const kr::TriangleMesh mesh = bigTriangle(100.0f);
  kr::RenderScene scene = darkScene();
  kr::Material material;
  material.albedo = {0.3f, 0.6f, 0.9f};
  scene.meshes.push_back({&mesh, material});
  scene.sun.direction = {0, 3, -3};  // 45 degrees to the triangle's normal, not normalised
  scene.sun.irradiance = {2.0f, 1.5f, 1.0f};
  scene.sun.angularDiameterDegrees = 0.0f;
  kr::RenderSettings settings;
  settings.width = 33;
  settings.height = 21;
  settings.samplesPerPixel = 2;
  const kr::Image image = kr::renderFrame(scene, settings);
  const Vector3f expected = material.albedo.cwiseProduct(scene.sun.irradiance) * (std::sqrt(0.5f) / kPi);
  const Vector3f centre = rgb(image, settings.width / 2, settings.height / 2);
  EXPECT_NEAR((centre - expected).cwiseAbs().maxCoeff(), 0.0f, 1e-5f) << centre.transpose();

  // Lit from behind, the triangle gets no direct light and is black.
  scene.sun.direction = {0, -1, 0};
  const kr::Image back = kr::renderFrame(scene, settings);
  EXPECT_NEAR(rgb(back, settings.width / 2, settings.height / 2).norm(), 0.0f, 1e-6f);
}

TEST(Tracer, QuadCastsHardShadowOnGround) {
  // Quad at height 1 over [-0.5, 0.5]^2; a point sun travelling along (1, 0, -1) puts its shadow
  // on the ground over x in [0.5, 1.5], y in [-0.5, 0.5]. Black sky: shadow = 0 exactly.
  kr::TriangleMesh quad;
  quad.positions = {{-0.5f, -0.5f, 1}, {0.5f, -0.5f, 1}, {0.5f, 0.5f, 1}, {-0.5f, 0.5f, 1}};
  quad.triangles = {{0, 1, 2}, {0, 2, 3}};
  kr::RenderScene scene = darkScene();
  scene.meshes.push_back({&quad, {}});
  scene.sun.direction = {1, 0, -1};
  scene.sun.irradiance = {2.0f, 2.0f, 2.0f};
  scene.sun.angularDiameterDegrees = 0.0f;
  scene.ground.enabled = true;
  scene.ground.checkerSize = 0.0f;  // plain albedoA
  scene.camera.position = {0, -8, 6};
  scene.camera.lookAt = {0.5f, 0, 0};
  kr::RenderSettings settings;
  settings.width = 160;
  settings.height = 120;
  settings.samplesPerPixel = 1;
  settings.maxDepth = 1;  // direct light only

  const kr::Image image = kr::renderFrame(scene, settings);
  const Eigen::Vector2i inShadow = project(scene.camera, settings, {1.0f, 0.0f, 0.0f});
  const Eigen::Vector2i lit = project(scene.camera, settings, {1.0f, 1.5f, 0.0f});
  // The point (1, 0, 0) is not hidden by the quad itself: the camera ray meets z = 1 at
  // (0.83, -1.33), outside the quad.
  const Vector3f expectedLit = scene.ground.albedoA * (2.0f * std::sqrt(0.5f) / kPi);
  EXPECT_LT(rgb(image, inShadow.x(), inShadow.y()).norm(), 1e-6f);
  EXPECT_LT((rgb(image, lit.x(), lit.y()) - expectedLit).norm(), 1e-4f);
}

TEST(Tracer, SunWithAngularSizeGivesHalfLightOnTheShadowEdge) {
  // A half-plane occluder (a huge quad over x < 0) at height 10 under a sun straight overhead:
  // at the point below the occluder's edge, exactly half of the sun's disk is hidden, so the
  // ground gets half the light (a hard sun gives 0 or 1). 2048 paths; each is lit with
  // probability 1/2, so the standard deviation of the mean is 0.5/sqrt(2048) = 0.011: bounds
  // 0.5 +- 0.06 are 5 sigma. 2 degrees of sun make a penumbra 0.35 m wide; the pixel covers
  // 0.03 m.
  kr::TriangleMesh half;
  half.positions = {{-1000, -1000, 10}, {0, -1000, 10}, {0, 1000, 10}, {-1000, 1000, 10}};
  half.triangles = {{0, 1, 2}, {0, 2, 3}};
  kr::RenderScene scene = darkScene();
  scene.meshes.push_back({&half, {}});
  setSun(scene, Vector3f{0, 0, -1}, 2.0f);
  addWhiteGround(scene);
  scene.camera.position = {0, -2, 5};
  scene.camera.lookAt = {0, 0, 0};
  kr::RenderSettings settings = renderSettings(1, 1, 2048, 1);
  scene.camera.verticalFovDegrees = 0.3f;
  const float edge = kr::renderFrame(scene, settings).at(0, 0).x();
  EXPECT_NEAR(edge, 0.5f, 0.06f);
  // 0.1 m beside the edge the occluder's edge is t = 0.01 rad / 0.01745 rad = 0.573 sun radii
  // from the sun's centre: the hidden segment is (acos t - t sqrt(1 - t^2)) / pi = 15.6 % of
  // the disk, so the ground gets 0.844 (sigma 0.008 with 2048 paths; bound 0.04). A hard sun
  // lights it fully.
  scene.camera.position = {0.1f, -2, 5};
  scene.camera.lookAt = {0.1f, 0, 0};
  const float t = 0.1f / 10.0f / (1.0f * kPi / 180.0f);
  const float visible = 1.0f - (std::acos(t) - t * std::sqrt(1 - t * t)) / kPi;
  EXPECT_NEAR(kr::renderFrame(scene, settings).at(0, 0).x(), visible, 0.04f);
  scene.sun.angularDiameterDegrees = 0.0f;
  EXPECT_NEAR(kr::renderFrame(scene, settings).at(0, 0).x(), 1.0f, 1e-5f);
}

TEST(Tracer, RectLightIrradianceMatchesTheFormFactor) {
  // A 2 x 2 m light of radiance L facing down at height h = 2 over a white ground: the ground
  // point below its centre has radiance albedo * L * F, F the point-to-rectangle form factor
  // (four a x b = 1 x 1 corner rectangles: F_corner = 1/(2 pi) [X/sqrt(1+X^2) atan(Y/sqrt(1+X^2))
  // + Y/sqrt(1+Y^2) atan(X/sqrt(1+Y^2))], X = a/h, Y = b/h). Area sampling: the per-path
  // relative spread is about 0.3, so 9 x 1024 paths give 0.3 % noise; bound 2 %.
  kr::RenderScene scene = darkScene();
  kr::RectLight light;
  light.corner = {-1, -1, 2};
  light.edgeU = {0, 2, 0};
  light.edgeV = {2, 0, 0};  // edgeU x edgeV = (0, 0, -4): emits downwards
  light.radiance = {3, 3, 3};
  scene.rectLights.push_back(light);
  addWhiteGround(scene);
  scene.camera.position = {0, -4, 1};
  scene.camera.lookAt = {0, 0, 0};
  scene.camera.verticalFovDegrees = 0.5f;
  kr::RenderSettings settings = renderSettings(3, 3, 1024, 1);
  const kr::Image image = kr::renderFrame(scene, settings);
  const float X = 0.5f, Y = 0.5f;
  const float corner = (X / std::sqrt(1 + X * X) * std::atan(Y / std::sqrt(1 + X * X)) +
                        Y / std::sqrt(1 + Y * Y) * std::atan(X / std::sqrt(1 + Y * Y))) / (2.0f * kPi);
  const float expected = 3.0f * 4.0f * corner;
  float mean = 0.0f;
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 3; ++x) mean += image.at(x, y).x() / 9.0f;
  EXPECT_NEAR(mean, expected, 0.02f * expected);

  // Seen directly (from below), the light shows its radiance; from above, its black back.
  scene.camera.position = {0, 0, 1};
  scene.camera.lookAt = {0, 0.1f, 2};
  settings.samplesPerPixel = 1;
  EXPECT_NEAR(kr::renderFrame(scene, settings).at(1, 1).x(), 3.0f, 1e-5f);
  scene.camera.position = {0, 0, 3};
  scene.camera.lookAt = {0, 0.1f, 0};
  EXPECT_NEAR(kr::renderFrame(scene, settings).at(1, 1).x(), 0.0f, 1e-6f);
}

TEST(Tracer, ImageDoesNotDependOnThreadCountButOnSeed) {
  kr::TriangleMesh mesh = bigTriangle(1.0f);
  mesh.normals = {Vector3f(-1, -1, 0).normalized(), Vector3f(1, -1, 0).normalized(), {0, -1, 0}};
  kr::RenderScene scene;
  kr::Material glass;
  glass.type = kr::MaterialType::Dielectric;
  scene.meshes.push_back({&mesh, {}});
  scene.spheres.push_back({{{0.5f, -1, 0.5f}}, {}, 0.4f, glass});
  scene.camera.position = {1, -6, 3};
  scene.camera.lookAt = {0, 0, 0};
  scene.camera.apertureRadius = 0.05f;
  kr::RenderSettings settings;
  settings.width = 97;  // not a multiple of the tile size
  settings.height = 61;
  settings.samplesPerPixel = 3;
  const auto render = [&](int threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<size_t>(threads));
    return kr::renderFrame(scene, settings);
  };
  const kr::Image one = render(1);
  const kr::Image two = render(2);
  ASSERT_EQ(one.width(), two.width());
  ASSERT_EQ(one.height(), two.height());
  bool uniform = true;
  for (int y = 0; y < one.height(); ++y)
    for (int x = 0; x < one.width(); ++x) {
      ASSERT_EQ(one.at(x, y), two.at(x, y)) << "pixel " << x << "," << y;
      uniform = uniform && one.at(x, y) == one.at(0, 0);
    }
  EXPECT_FALSE(uniform);  // something was rendered
  settings.seed = 7;
  const kr::Image other = render(2);
  int differing = 0;
  for (int y = 0; y < one.height(); ++y)
    for (int x = 0; x < one.width(); ++x) differing += other.at(x, y) != one.at(x, y);
  EXPECT_GT(differing, one.width() * one.height() / 4) << "the seed changes the noise";
}

TEST(Tracer, VertexNormalsAreInterpolatedAcrossFlatTriangle) {
  kr::TriangleMesh flat = bigTriangle(3.0f);
  kr::TriangleMesh smooth = flat;
  smooth.normals = {Vector3f(-2, -1, 0).normalized(), Vector3f(2, -1, 0).normalized(), {0, -1, 0}};
  kr::RenderScene scene = darkScene();
  setSun(scene, Vector3f{0, 1, 0}, 0.0f);  // along the view direction: shading = n . (0, -1, 0)
  kr::RenderSettings settings;
  settings.width = 64;
  settings.height = 64;
  settings.samplesPerPixel = 1;
  kr::Material white;
  white.albedo = {1, 1, 1};
  scene.meshes.push_back({&flat, white});
  const kr::Image flatImage = kr::renderFrame(scene, settings);
  scene.meshes[0].mesh = &smooth;
  const kr::Image smoothImage = kr::renderFrame(scene, settings);

  // Pixels in the lower half of the triangle, left of centre, at the centre, right of centre.
  // Sample positions are jittered inside the pixel: the normal varies by < 0.01 across one.
  const int row = 40;
  for (int x : {13, 32, 50}) {
    const Vector3f p = pixelCentreOnPlaneY0(scene.camera, settings, x, row);
    // Barycentrics of p (in the x-z plane) for vertices (-3,-3), (3,-3), (0,3).
    const float v = (p.z() + 3.0f) / 6.0f;
    const float u = (p.x() + 3.0f - 3.0f * v) / 6.0f;
    ASSERT_GT(1.0f - u - v, 0.0f);
    ASSERT_GT(u, 0.0f);
    const Vector3f n = ((1 - u - v) * smooth.normals[0] + u * smooth.normals[1] + v * smooth.normals[2]).normalized();
    EXPECT_NEAR(flatImage.at(x, row).x(), 1.0f, 1e-5f) << "flat shading is uniform, x=" << x;
    EXPECT_NEAR(smoothImage.at(x, row).x(), -n.y(), 0.01f) << "x=" << x;
  }
  EXPECT_GT(smoothImage.at(32, row).x() - smoothImage.at(13, row).x(), 0.08f);
  EXPECT_NEAR(smoothImage.at(13, row).x(), smoothImage.at(50, row).x(), 0.01f);  // mirror symmetric
}

TEST(Tracer, ClipPlaneRemovesOneSideAndAlphaMarksCoverage) {
  // A diffuse sphere in a uniform white environment (radiance 1) renders as its albedo
  // (furnace); the clip plane x = 0 with normal -x removes its left half, which then shows the
  // environment, or alpha 0 with a transparent background.
  kr::RenderScene scene = darkScene();
  scene.environment.zenith = {1, 1, 1};
  kr::Material grey;
  grey.albedo = {0.5f, 0.5f, 0.5f};
  scene.spheres.push_back({{{0, 0, 0}}, {}, 1.0f, grey});
  scene.clip = {true, {0, 0, 0}, {-1, 0, 0}};
  kr::RenderSettings settings;
  settings.environmentSampling = false;  // exact values: BSDF sampling alone is noise-free here
  settings.width = 40;
  settings.height = 40;
  settings.samplesPerPixel = 1;
  const Eigen::Vector2i left = project(scene.camera, settings, {-0.5f, -1, 0});
  const Eigen::Vector2i right = project(scene.camera, settings, {0.5f, -1, 0});
  const kr::Image image = kr::renderFrame(scene, settings);
  EXPECT_NEAR(image.at(left.x(), left.y()).x(), 1.0f, 1e-5f);
  EXPECT_NEAR(image.at(right.x(), right.y()).x(), 0.5f, 1e-5f);
  settings.transparentBackground = true;
  const kr::Image alpha = kr::renderFrame(scene, settings);
  EXPECT_EQ(alpha.at(left.x(), left.y())[3], 0.0f);
  EXPECT_EQ(alpha.at(right.x(), right.y())[3], 1.0f);
  EXPECT_EQ(alpha.at(0, 0)[3], 0.0f);
  EXPECT_NEAR(alpha.at(right.x(), right.y()).x(), 0.5f, 1e-5f) << "straight (not premultiplied) colour";
}

TEST(Camera, KeysAreInterpolatedThroughEveryKeyAndHeldOutside) {
  kr::Camera base;
  base.apertureRadius = 0.1f;
  std::vector<kr::CameraKey> keys(3);
  keys[0] = {0.0, {0, 0, 0}, {0, 1, 0}, 30.0f};
  keys[1] = {1.0, {2, 0, 0}, {2, 1, 0}, 40.0f};
  keys[2] = {3.0, {2, 4, 0}, {2, 5, 0}, 50.0f};
  EXPECT_EQ(kr::cameraAt(base, {}, 1.5).position, base.position) << "no keys: the base camera";
  for (const kr::CameraKey& k : keys) {
    const kr::Camera c = kr::cameraAt(base, keys, k.time);
    EXPECT_LT((c.position - k.position).norm(), 1e-6f) << k.time;
    EXPECT_FLOAT_EQ(c.verticalFovDegrees, k.verticalFovDegrees);
    EXPECT_EQ(c.apertureRadius, 0.1f);
  }
  EXPECT_EQ(kr::cameraAt(base, keys, -1.0).position, keys[0].position);
  EXPECT_EQ(kr::cameraAt(base, keys, 9.0).lookAt, keys[2].lookAt);
  // Two keys: the spline is the straight line at mid time.
  const std::vector<kr::CameraKey> two(keys.begin(), keys.begin() + 2);
  EXPECT_LT((kr::cameraAt(base, two, 0.5).position - Vector3f(1, 0, 0)).norm(), 1e-6f);
  // Continuity: no jump across a key.
  const Vector3f before = kr::cameraAt(base, keys, 1.0 - 1e-4).position;
  const Vector3f after = kr::cameraAt(base, keys, 1.0 + 1e-4).position;
  EXPECT_LT((before - after).norm(), 1e-3f);
}

TEST(Camera, DepthOfFieldBlursOnlyOutOfFocus) {
  // A checker ground seen from above: in focus (focus distance = camera height) the pixels
  // match the pinhole image; focused far away, the checker is blurred (pixels move towards
  // the mean albedo).
  kr::RenderScene scene = darkScene();
  scene.environment.zenith = {1, 1, 1};
  scene.ground.enabled = true;
  scene.ground.checkerSize = 0.5f;
  scene.ground.albedoA = {0.9f, 0.9f, 0.9f};
  scene.ground.albedoB = {0.1f, 0.1f, 0.1f};
  scene.camera.position = {0.1f, 0.1f, 5};
  scene.camera.lookAt = {0.1f, 0.1f, 0};
  scene.camera.up = {0, 1, 0};
  scene.camera.verticalFovDegrees = 30.0f;
  kr::RenderSettings settings;
  settings.width = 32;
  settings.height = 32;
  settings.samplesPerPixel = 64;
  const auto contrast = [&](const kr::Image& image) {
    double sum = 0.0;
    for (int y = 0; y < image.height(); ++y)
      for (int x = 0; x < image.width(); ++x) sum += std::abs(image.at(x, y).x() - 0.5f);
    return sum / (image.width() * image.height());
  };
  const double pinhole = contrast(kr::renderFrame(scene, settings));
  scene.camera.apertureRadius = 0.3f;
  scene.camera.focusDistance = 5.0f;
  const double focused = contrast(kr::renderFrame(scene, settings));
  scene.camera.focusDistance = 50.0f;
  const double blurred = contrast(kr::renderFrame(scene, settings));
  EXPECT_NEAR(focused, pinhole, 0.02);
  EXPECT_LT(blurred, 0.6 * pinhole);
}

TEST(Tracer, EnvironmentImageIsEquirectangularWithZUp) {
  // An 8 x 4 latitude-longitude image: the top half (elevation > 0) red, the bottom half blue,
  // and the column centred on azimuth 0 (+x) of the upper half green.
  auto sky = std::make_shared<kr::Image>(8, 4, Eigen::Vector4f(0, 0, 1, 1));
  for (int x = 0; x < 8; ++x)
    for (int y = 0; y < 2; ++y) sky->at(x, y) = Eigen::Vector4f(1, 0, 0, 1);
  sky->at(4, 1) = Eigen::Vector4f(0, 1, 0, 1);  // u in [0.5, 0.625): azimuth [0, 45) degrees
  kr::Environment e;
  e.type = kr::EnvironmentType::Image;
  e.image = sky;
  e.intensity = 2.0f;
  EXPECT_EQ(kr::environmentRadiance(e, {0, 0, 1}), Vector3f(2, 0, 0));
  EXPECT_EQ(kr::environmentRadiance(e, {0, 0, -1}), Vector3f(0, 0, 2));
  EXPECT_EQ(kr::environmentRadiance(e, Vector3f(1, 0.2f, 0.3f).normalized()), Vector3f(0, 2, 0));
  EXPECT_EQ(kr::environmentRadiance(e, Vector3f(-1, 0.2f, 0.3f).normalized()), Vector3f(2, 0, 0));
  e.rotationDegrees = 180.0f;  // the green column now spans azimuth [180, 225) degrees
  EXPECT_EQ(kr::environmentRadiance(e, Vector3f(-1, -0.2f, 0.3f).normalized()), Vector3f(0, 2, 0));
}

namespace {

// A 10 x 10 m slab, z in [1, 2], its faces outward and each split along its diagonal.
kr::TriangleMesh slabZ1To2() {
  kr::TriangleMesh slab;
  const float s = 5.0f;
  slab.positions = {{-s, -s, 1}, {s, -s, 1}, {s, s, 1}, {-s, s, 1}, {-s, -s, 2}, {s, -s, 2}, {s, s, 2}, {-s, s, 2}};
  slab.triangles = {{0, 2, 1}, {0, 3, 2}, {4, 5, 6}, {4, 6, 7}, {0, 1, 5}, {0, 5, 4},
                    {1, 2, 6}, {1, 6, 5}, {2, 3, 7}, {2, 7, 6}, {3, 0, 4}, {3, 4, 7}};
  return slab;
}

}  // namespace

TEST(Tracer, TransmissiveShadowsPassWaterWithFresnelAndAbsorption) {
  // A glass slab (n = 1.5, absorption 0.5 / m, 1 m thick, z in [1, 2]) over a white ground, a
  // point sun straight down with E = pi, black sky, direct light only, and the camera below the
  // slab: the ground under the slab gets E T / pi with T = (1 - F0)^2 exp(-0.5), F0 = 0.04
  // (normal incidence in and out; no noise). The ray offset against self-intersection (1e-4 of
  // the scene's size, 0.5 mm here) shortens the path inside by up to 1 mm: tolerance 5e-4.
  // Without transmissive shadows the ground under the slab is black.
  const kr::TriangleMesh slab = slabZ1To2();
  kr::Material glass;
  glass.type = kr::MaterialType::Dielectric;
  glass.ior = 1.5f;
  glass.absorption = {0.5f, 0.5f, 0.5f};
  kr::RenderScene scene = darkScene();
  scene.meshes.push_back({&slab, glass});
  setSun(scene, Vector3f{0, 0, -1}, 0.0f);
  addWhiteGround(scene);
  scene.camera.position = {0, -2, 0.5f};
  scene.camera.lookAt = {0, 0, 0};
  kr::RenderSettings settings = renderSettings(3, 3, 4, 1);
  const float expected = 0.96f * 0.96f * std::exp(-0.5f);
  EXPECT_NEAR(kr::renderFrame(scene, settings).at(1, 1).x(), expected, 5e-4f);
  settings.transmissiveShadows = false;
  EXPECT_NEAR(kr::renderFrame(scene, settings).at(1, 1).x(), 0.0f, 1e-6f);
}

TEST(EmbreeScene, CrossingsCountEachSurfaceOnceAndStopAtOpaqueOnes) {
  // A glass slab (z in [1, 2]) whose faces are split along their diagonals x = y: a vertical ray
  // on the diagonal meets both triangles of each face at the same distance, and must count one
  // crossing per face, with outward normals (down at z = 1, up at z = 2). An opaque sphere above
  // the slab makes the ray occluded (-1), the clip plane below it removes it again, and a slab
  // the ray crosses more often than there is room for is occluded too.
  const kr::TriangleMesh slab = slabZ1To2();
  kr::Material glass;
  glass.type = kr::MaterialType::Dielectric;
  glass.ior = 1.5f;
  kr::RenderScene scene;
  scene.meshes.push_back({&slab, glass});
  kr::EmbreeScene geometry;
  geometry.update(scene);
  kr::RayCounters counters;
  kr::Crossing out[4];
  const Vector3f origin(1, 1, 0), up(0, 0, 1);
  const float inf = std::numeric_limits<float>::infinity();
  ASSERT_EQ(geometry.crossings(origin, up, inf, counters, out, 4), 2);
  std::sort(out, out + 2, [](const kr::Crossing& a, const kr::Crossing& b) { return a.t < b.t; });
  EXPECT_NEAR(out[0].t, 1.0f, 1e-5f);
  EXPECT_NEAR(out[1].t, 2.0f, 1e-5f);
  EXPECT_NEAR(out[0].ng.z(), -1.0f, 1e-6f);
  EXPECT_NEAR(out[1].ng.z(), 1.0f, 1e-6f);
  EXPECT_EQ(out[0].material->type, kr::MaterialType::Dielectric);
  EXPECT_EQ(geometry.crossings(origin, up, 1.5f, counters, out, 4), 1);  // the segment ends inside
  EXPECT_EQ(geometry.crossings(origin, up, inf, counters, out, 1), -1);  // no room for the second

  kr::SphereSet ball;
  ball.centres = {{1, 1, 4}};
  ball.radius = 0.5f;
  scene.spheres.push_back(ball);
  geometry.update(scene);
  EXPECT_EQ(geometry.crossings(origin, up, inf, counters, out, 4), -1);
  EXPECT_EQ(geometry.crossings(origin, up, 3.0f, counters, out, 4), 2);  // stops short of the ball
  scene.clip.enabled = true;
  scene.clip.point = {0, 0, 3};
  scene.clip.normal = {0, 0, 1};  // removes z > 3: the ball
  geometry.update(scene);
  EXPECT_EQ(geometry.crossings(origin, up, inf, counters, out, 4), 2);
}

namespace {

// A tube along x through the given x positions (a straight B-spline), radius linear from r0 to r1.
kr::CurveSet tubeAlongX(std::vector<float> xs, float r0, float r1, kr::Material material = {}) {
  kr::Tube tube;
  for (size_t i = 0; i < xs.size(); ++i) {
    tube.points.emplace_back(xs[i], 0.0f, 0.0f);
    tube.radii.push_back(r0 + (r1 - r0) * float(i) / float(xs.size() - 1));
  }
  return {{tube}, material};
}

// Height in pixels of the vertical extent, seen from the camera, of a circle of radius r in the
// plane x = const at distance d from the camera (d along the view, which is +y): 2 tan(asin(r/d)),
// in pixels.
float projectedDiameter(const kr::Camera& camera, const kr::RenderSettings& s, float r, float d) {
  const float tanHalf = std::tan(0.5f * camera.verticalFovDegrees * kPi / 180.0f);
  return 2.0f * std::tan(std::asin(r / d)) / tanHalf * 0.5f * float(s.height);
}

float columnCoverage(const kr::Image& image, int x) {
  float sum = 0.0f;
  for (int y = 0; y < image.height(); ++y) sum += image.at(x, y)[3];
  return sum;
}

float rowCoverage(const kr::Image& image, int y) {
  float sum = 0.0f;
  for (int x = 0; x < image.width(); ++x) sum += image.at(x, y)[3];
  return sum;
}

// The alpha-only view of darkScene(): transparent background, coverage in alpha.
kr::RenderSettings coverageSettings() {
  kr::RenderSettings settings;
  settings.width = 240;
  settings.height = 201;  // odd: the middle row is centred on the tube's axis
  settings.samplesPerPixel = 16;
  settings.maxDepth = 1;
  settings.transparentBackground = true;
  return settings;
}

}  // namespace

TEST(Tracer, StraightTubeIsTwiceItsRadiusWideAndEndsInHemispheres) {
  // A tube of radius r = 0.25 through (-1, 0, 0), (0, 0, 0), (1, 0, 0), 5 m in front of the camera.
  // Summed alpha down a column is the covered height in pixels: the circle's silhouette,
  // 2 tan(asin(r / d)) with d the distance to the axis. Along the middle row the tube reaches
  // from x = -1 to 1 (the mirrored end control points make the B-spline start and end there) and
  // the hemispherical caps add r at each end: the row is covered between the tangents to the
  // end spheres, at angles atan(1 / 5) + asin(r / sqrt(26)) either side. 16 stratified samples
  // per pixel estimate each edge pixel's coverage to about 1/16: tolerance 1 pixel.
  const float r = 0.25f;
  kr::RenderScene scene = darkScene();
  scene.curves.push_back(tubeAlongX({-1, 0, 1}, r, r));
  const kr::RenderSettings settings = coverageSettings();
  const kr::Image image = kr::renderFrame(scene, settings);
  for (float x : {-0.5f, 0.0f, 0.7f}) {
    const int column = project(scene.camera, settings, {x, 0, 0}).x();
    EXPECT_NEAR(columnCoverage(image, column), projectedDiameter(scene.camera, settings, r, std::hypot(5.0f, x)), 1.0f)
        << "x = " << x;
  }
  const float tanHalf = std::tan(0.5f * scene.camera.verticalFovDegrees * kPi / 180.0f);
  const float edge = std::tan(std::atan(0.2f) + std::asin(r / std::sqrt(26.0f)));  // screen-plane x at distance 1
  const float length = 2.0f * edge / tanHalf * 0.5f * float(settings.height);
  EXPECT_NEAR(rowCoverage(image, settings.height / 2), length, 1.0f);
  // On the axis's row, a pixel seen only through a cap (past the tube's end circle, whose nearest
  // point projects to x = 1 / 4.75 = 0.21, before the cap's edge at 0.25) is covered; the
  // pixel beyond it is not.
  const int row = settings.height / 2;
  EXPECT_EQ(image.at(project(scene.camera, settings, {1.15f, 0, 0}).x(), row)[3], 1.0f);
  EXPECT_EQ(image.at(project(scene.camera, settings, {-1.15f, 0, 0}).x(), row)[3], 1.0f);
  EXPECT_EQ(image.at(project(scene.camera, settings, {1.3f, 0, 0}).x(), row)[3], 0.0f);
}

TEST(Tracer, TaperedTubeFollowsItsRadii) {
  // Radii 0.4, 0.25, 0.1 at x = -1.5, 0, 1.5: linear control values give the linear radius
  // r(x) = 0.25 - 0.1 x, so the tube is 0.7 m thick at x = -1 and 0.3 m at x = 1 (tolerance as
  // above; the cone's slope changes the silhouette by far less than a pixel here).
  kr::RenderScene scene = darkScene();
  scene.curves.push_back(tubeAlongX({-1.5f, 0, 1.5f}, 0.4f, 0.1f));
  const kr::RenderSettings settings = coverageSettings();
  const kr::Image image = kr::renderFrame(scene, settings);
  float previous = std::numeric_limits<float>::infinity();
  for (float x : {-1.0f, -0.5f, 0.0f, 0.5f, 1.0f}) {
    const int column = project(scene.camera, settings, {x, 0, 0}).x();
    const float height = columnCoverage(image, column);
    EXPECT_NEAR(height, projectedDiameter(scene.camera, settings, 0.25f - 0.1f * x, std::hypot(5.0f, x)), 1.0f)
        << "x = " << x;
    EXPECT_LT(height, previous - 3.0f) << "narrower towards the thin end, x = " << x;
    previous = height;
  }
}

TEST(Tracer, TubeIsLambertShadedWithItsOutwardNormalAndCastsAShadow) {
  // A white diffuse tube (radius 0.5 along x) lit by a point sun travelling along the view
  // direction (+y) with E = pi: radiance = cos(n, -y) = sqrt(1 - (z/r)^2) at the point of height
  // z where the camera ray meets the cylinder (computed exactly per pixel centre; a pixel spans
  // 0.01 r, so the jittered samples change the value by < 0.005 at z = 0.6 r): the normal is the
  // surface's, not the curve's tangent or a ray-facing ribbon's.
  kr::RenderScene scene = darkScene();
  kr::Material white;
  white.albedo = {1, 1, 1};
  const float r = 0.5f;
  scene.curves.push_back(tubeAlongX({-2, 0, 2}, r, r, white));
  setSun(scene, Vector3f{0, 1, 0}, 0.0f);
  scene.camera.verticalFovDegrees = 12.0f;
  kr::RenderSettings settings = renderSettings(64, 201, 4, 1);
  const kr::Image image = kr::renderFrame(scene, settings);
  const float tanHalf = std::tan(0.5f * scene.camera.verticalFovDegrees * kPi / 180.0f);
  int checked = 0;
  for (int row = 0; row < settings.height; ++row) {
    // The ray (0, -5, 0) + t (0, 1, dz) meets y^2 + z^2 = r^2 where (t - 5)^2 + (t dz)^2 = r^2.
    const float dz = (1.0f - 2.0f * (row + 0.5f) / settings.height) * tanHalf;
    const float a = 1.0f + dz * dz, b = -10.0f, c = 25.0f - r * r;
    const float discriminant = b * b - 4.0f * a * c;
    if (discriminant < 0.0f) continue;
    const float t = (-b - std::sqrt(discriminant)) / (2.0f * a);
    const float z = t * dz;
    if (std::abs(z) > 0.9f * r) continue;  // the silhouette's last pixels are partly covered
    EXPECT_NEAR(image.at(settings.width / 2, row).x(), std::sqrt(1.0f - z * z / (r * r)), 0.01f) << "row " << row;
    ++checked;
  }
  EXPECT_GT(checked, 50);

  // A sun travelling along (0, 1, -1) casts the tube's shadow on the ground z = -1 over the strip
  // |y - 1| < r sqrt(2): black there (black sky, direct light only), E cos 45 / pi = 0.707 beside
  // it (|y - 1| = 1.2). The camera on the +y side sees both points past the tube.
  addWhiteGround(scene);
  scene.ground.point = {0, 0, -1};
  scene.sun.direction = {0, 1, -1};
  scene.camera.position = {0, 8, 6};
  scene.camera.lookAt = {0, 1, -1};
  scene.camera.verticalFovDegrees = 45.0f;
  settings.width = 80;
  settings.height = 80;
  const kr::Image top = kr::renderFrame(scene, settings);
  const Eigen::Vector2i shadow = project(scene.camera, settings, {1.0f, 1.0f, -1});
  const Eigen::Vector2i lit = project(scene.camera, settings, {1.0f, 2.2f, -1});
  EXPECT_LT(rgb(top, shadow.x(), shadow.y()).maxCoeff(), 1e-6f);
  EXPECT_NEAR(rgb(top, lit.x(), lit.y()).x(), std::sqrt(0.5f), 1e-4f);
}

TEST(Tracer, ClipPlaneRemovesTubesAndTheirCaps) {
  // The plane x = 0 with normal +x removes the right half of the tube, its cap included.
  kr::RenderScene scene = darkScene();
  scene.curves.push_back(tubeAlongX({-1, 0, 1}, 0.25f, 0.25f));
  const kr::RenderSettings settings = coverageSettings();
  const int row = settings.height / 2;
  const auto alphaAt = [&](const kr::Image& image, float x) {
    return image.at(project(scene.camera, settings, {x, 0, 0}).x(), row)[3];
  };
  const kr::Image whole = kr::renderFrame(scene, settings);
  scene.clip = {true, {0, 0, 0}, {1, 0, 0}};
  const kr::Image clipped = kr::renderFrame(scene, settings);
  for (float x : {-1.15f, -0.5f, 0.5f, 1.15f}) EXPECT_EQ(alphaAt(whole, x), 1.0f) << x;
  for (float x : {-1.15f, -0.5f}) EXPECT_EQ(alphaAt(clipped, x), 1.0f) << x;
  for (float x : {0.5f, 1.15f}) EXPECT_EQ(alphaAt(clipped, x), 0.0f) << x;
}

TEST(Tracer, TranslucentTubeIsClosedFurnace) {
  // Furnace: a translucent tube of tint rho and IOR 1 in a uniform environment of radiance 1.
  // A straight tube of constant radius closed by its hemispherical caps is convex, so every
  // camera path enters once (x rho), meets the inside once (x rho) and leaves: rho^2 exactly, at
  // every fully covered pixel, caps included. An open end, a cap's inner half left in the way or
  // a normal facing the wrong way changes some paths' weight (rho, rho^3, or ends the path).
  kr::RenderScene scene = darkScene();
  scene.environment.zenith = {1, 1, 1};
  kr::Material tint;
  tint.type = kr::MaterialType::Translucent;
  tint.albedo = {0.8f, 0.6f, 0.4f};
  tint.ior = 1.0f;
  scene.curves.push_back(tubeAlongX({-1, -0.4f, 0.2f, 0.8f}, 0.4f, 0.4f, tint));
  kr::RenderSettings settings = coverageSettings();
  settings.environmentSampling = false;  // zero-variance furnace with BSDF sampling alone
  settings.maxDepth = 16;
  const kr::Image image = kr::renderFrame(scene, settings);
  const Vector3f expected = tint.albedo.cwiseProduct(tint.albedo);
  int covered = 0, onCaps = 0;
  const int leftCap = project(scene.camera, settings, {-1.0f, -0.4f, 0}).x();
  const int rightCap = project(scene.camera, settings, {0.8f, -0.4f, 0}).x();
  for (int y = 0; y < image.height(); ++y)
    for (int x = 0; x < image.width(); ++x) {
      if (image.at(x, y)[3] < 1.0f) continue;
      ASSERT_LT((rgb(image, x, y) - expected).cwiseAbs().maxCoeff(), 1e-4f) << "pixel " << x << "," << y;
      ++covered;
      onCaps += x < leftCap || x > rightCap;
    }
  EXPECT_GT(covered, 2000);
  EXPECT_GT(onCaps, 200);
}

TEST(Tracer, AbsorbingDielectricTubeAcrossItsDiameterFollowsBeerLambert) {
  // As Absorption.DielectricSphereThroughItsCentreFollowsBeerLambert (test_render_validation.cpp)
  // for a tube of radius 1 seen across its axis: at normal incidence every reflection and
  // refraction stays on the diameter, so L = F0 + (1-F0)^2 a / (1 - F0 a), a = exp(-2 sigma R);
  // noise bound 0.01 as there. Entering and leaving are told by the outward normal: a normal
  // facing into the tube would put the absorption outside it (L = 1).
  kr::RenderScene scene = darkScene();
  scene.environment.zenith = {1, 1, 1};
  kr::Material glass;
  glass.type = kr::MaterialType::Dielectric;
  glass.ior = 1.5f;
  glass.absorption = {0.5f, 0.1f, 0.0f};
  scene.curves.push_back(tubeAlongX({-2, 0, 2}, 1.0f, 1.0f, glass));
  scene.camera.verticalFovDegrees = 0.2f;
  kr::RenderSettings settings = renderSettings(1, 1, 4096, 64);
  const Vector3f v = kr::renderFrame(scene, settings).at(0, 0).head<3>();
  const float f0 = (0.5f / 2.5f) * (0.5f / 2.5f);
  for (int c = 0; c < 3; ++c) {
    const float a = std::exp(-glass.absorption[c] * 2.0f);
    EXPECT_NEAR(v[c], f0 + (1 - f0) * (1 - f0) * a / (1 - f0 * a), 0.01f) << "channel " << c;
  }
}

TEST(Tracer, ImageWithTubesDoesNotDependOnThreadCount) {
  kr::RenderScene scene;
  kr::Material body;
  body.type = kr::MaterialType::Translucent;
  body.albedo = {0.95f, 0.6f, 0.5f};
  body.absorption = {0.05f, 0.4f, 0.5f};
  kr::Tube arm;
  arm.points = {{0, 0, 2}, {0.2f, 0.1f, 1.5f}, {0.1f, 0.3f, 1.0f}, {0.3f, 0.2f, 0.5f}};
  arm.radii = {0.2f, 0.15f, 0.1f, 0.05f};
  scene.curves.push_back({{arm, kr::Tube{{{-1, 0, 1}, {-0.5f, 0, 1.2f}}, {0.1f, 0.1f}}}, body});
  scene.camera.position = {1, -5, 2};
  scene.camera.lookAt = {0, 0, 1};
  kr::RenderSettings settings;
  settings.width = 61;
  settings.height = 47;
  settings.samplesPerPixel = 3;
  const auto render = [&](int threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<size_t>(threads));
    return kr::renderFrame(scene, settings);
  };
  const kr::Image one = render(1);
  const kr::Image two = render(2);
  scene.curves.clear();
  const kr::Image without = render(2);
  int differing = 0;
  for (int y = 0; y < one.height(); ++y)
    for (int x = 0; x < one.width(); ++x) {
      ASSERT_EQ(one.at(x, y), two.at(x, y)) << "pixel " << x << "," << y;
      differing += one.at(x, y) != without.at(x, y);
    }
  EXPECT_GT(differing, 50) << "the tubes were drawn";
}

TEST(Tracer, BadTubesAreRefused) {
  kr::RenderScene scene = darkScene();
  kr::RenderSettings settings;
  settings.width = settings.height = 4;
  scene.curves.push_back(tubeAlongX({-1, 1}, 0.1f, 0.1f));
  EXPECT_NO_THROW(kr::renderFrame(scene, settings));
  scene.curves[0].tubes[0].radii.pop_back();
  EXPECT_THROW(kr::renderFrame(scene, settings), std::invalid_argument);
  scene.curves[0].tubes[0].radii = {0.1f, 0.0f};
  EXPECT_THROW(kr::renderFrame(scene, settings), std::invalid_argument);
  scene.curves[0].tubes[0].radii = {0.1f, 0.1f};
  scene.curves[0].tubes[0].points[1].x() = std::numeric_limits<float>::quiet_NaN();
  EXPECT_THROW(kr::renderFrame(scene, settings), std::invalid_argument);
}

namespace {

namespace kp = kurage::pipeline;

// A scene with a box body (kind 1) and a free chain hanging from (0, 0, 4) to (0, 0, 1) (kind 2,
// 7 particles 0.5 m apart), seen from the front against the sky, rendering 48 x 64 with alpha.
kp::Scene chainScene() {
  const nlohmann::json document = nlohmann::json::parse(R"({
    "name": "chain",
    "container": {"min": [-3, -3, 0], "max": [3, 3, 6]},
    "bodies": [
      {"name": "block", "shape": "box", "min": [1.5, -0.5, 0], "max": [2.5, 0.5, 1]},
      {"name": "arm", "shape": "chain", "start": [0, 0, 4], "end": [0, 0, 1], "spacing": 0.5,
       "pins": [{"select": "rim"}]}
    ],
    "output": {"duration": 1, "fps": 1},
    "render": {
      "width": 48, "height": 64, "samples": 4, "transparent_background": true,
      "camera": {"position": [0, -8, 2.5], "look_at": [0, 0, 2.5], "up": [0, 0, 1], "fov": 40},
      "ground": {"enabled": false},
      "chain_radius": {"root": 0.4, "tip": 0.1}
    }
  })");
  return kp::parseScene(document, "chain.json");
}

}  // namespace

TEST(ChainTubes, OneTubePerChainInIdOrderTaperingFromRootToTip) {
  const kp::Scene scene = chainScene();
  ASSERT_TRUE(kp::hasChains(scene));
  // A hand-made frame: fluid and block particles around, the chain's 7 particles shuffled, their
  // ids increasing from the top (z = 4) down.
  kp::ParticleFrame frame;
  const auto add = [&](float x, float y, float z, int64_t id, int32_t kind) {
    frame.px.push_back(x), frame.py.push_back(y), frame.pz.push_back(z);
    frame.vx.push_back(0), frame.vy.push_back(0), frame.vz.push_back(0);
    frame.id.push_back(id), frame.kind.push_back(kind);
  };
  add(2, 0, 0.5f, 0, 1);
  add(2, 0.2f, 0.5f, 1, 1);
  for (int k : {3, 0, 6, 1, 5, 2, 4}) add(0.01f * float(k), 0, 4.0f - 0.5f * float(k), 10 + k, 2);
  add(-1, 0, 1, 20, 0);
  const kr::CurveSet set = kp::chainTubes(scene, frame);
  ASSERT_EQ(set.tubes.size(), 1u);
  const kr::Tube& tube = set.tubes[0];
  ASSERT_EQ(tube.points.size(), 7u);
  ASSERT_EQ(tube.radii.size(), 7u);
  for (int k = 0; k < 7; ++k) {
    EXPECT_EQ(tube.points[size_t(k)], Vector3f(0.01f * float(k), 0, 4.0f - 0.5f * float(k))) << k;
    EXPECT_NEAR(tube.radii[size_t(k)], 0.4f - 0.05f * float(k), 1e-6f) << k;
  }
  EXPECT_EQ(set.material.albedo, scene.render.chainMaterial.albedo);
  EXPECT_EQ(set.material.type, kr::MaterialType::Translucent);
}

TEST(ChainTubes, RenderStageDrawsChainsFromTheParticleCache) {
  // sim, surface and render of frame 0 (the chain as built: vertical, x = 0, z from 4 down to 1):
  // the render stage reads the particle cache and draws the tube, so the column of x = 0 is
  // covered (alpha 1) between z = 1.5 and 3.5 and empty 0.8 m beside it, and the tube shows
  // the chain material's orange-pink tint (red above blue) where the sky behind is blue. Without
  // the particle cache the render stage refuses to run, naming `kurage sim`.
  const kp::Scene scene = chainScene();
  kurage::test::TempDir dir;
  kp::StageOptions options;
  options.outDir = dir.path();
  options.lastFrame = 0;
  kp::RunRecord record(dir.path(), scene, "chain.json");
  kp::runSimStage(scene, options, record);
  kp::runSurfaceStage(scene, options, record);
  kp::runRenderStage(scene, options, record);
  const kr::Image image = kr::readPng(kp::frameFile(dir.path() / "frames", 0, "png"));
  kr::Camera camera;
  camera.position = {0, -8, 2.5f};
  camera.lookAt = {0, 0, 2.5f};
  camera.up = {0, 0, 1};
  camera.verticalFovDegrees = 40.0f;
  kr::RenderSettings settings;
  settings.width = image.width();
  settings.height = image.height();
  for (float z : {1.5f, 2.5f, 3.5f}) {
    const Eigen::Vector2i on = project(camera, settings, {0, 0, z});
    const Eigen::Vector2i beside = project(camera, settings, {0.8f, 0, z});
    EXPECT_EQ(image.at(on.x(), on.y())[3], 1.0f) << "z = " << z;
    EXPECT_EQ(image.at(beside.x(), beside.y())[3], 0.0f) << "z = " << z;
    EXPECT_GT(image.at(on.x(), on.y()).x(), image.at(on.x(), on.y()).z() + 0.05f) << "z = " << z;
  }
  std::filesystem::remove(kp::frameFile(dir.path() / "particles", 0, "vdb"));
  options.force = true;  // the frame is up to date: redo it
  try {
    kp::runRenderStage(scene, options, record);
    FAIL() << "rendered a chain scene without its particle cache";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("kurage sim"), std::string::npos) << e.what();
  }
}

namespace {

// An emitter 2 m above a 4 m tank's rim (container [-3,3]^2 x [0,6], walls drawn 4 m high),
// pointing down and towards -x, seen from the front against the sky (48 x 64, alpha).
kp::Scene faucetScene(bool faucets) {
  nlohmann::json document = nlohmann::json::parse(R"({
    "name": "faucet",
    "container": {"min": [-3, -3, 0], "max": [3, 3, 6]},
    "fluid_blocks": [{"min": [-3, -3, 0], "max": [3, 3, 1]}],
    "emitters": [{"position": [1, 0, 4], "direction": [-0.5, 0, -1], "radius": 0.5, "speed": 2,
                  "start": 0, "end": 1}],
    "output": {"duration": 1, "fps": 1},
    "render": {
      "width": 48, "height": 64, "samples": 2, "transparent_background": true,
      "camera": {"position": [0, -14, 5], "look_at": [0, 0, 5], "up": [0, 0, 1], "fov": 40},
      "ground": {"enabled": false},
      "tank": {"enabled": true, "height": 4},
      "faucets": {"enabled": false}
    }
  })");
  document["render"]["faucets"]["enabled"] = faucets;
  return kp::parseScene(document, "faucet.json");
}

}  // namespace

TEST(Faucets, APipeEndsAtEachNozzleAlongItsJetAndRisesAboveTheRim) {
  const kp::Scene scene = faucetScene(true);
  const kr::CurveSet set = kp::faucetTubes(scene);
  ASSERT_EQ(set.tubes.size(), 1u);
  const kr::Tube& tube = set.tubes[0];
  ASSERT_EQ(tube.points.size(), 3u);
  const Vector3f d = Vector3f(-0.5f, 0, -1).normalized();
  const float radius = kp::kFaucetRadiusScale * 0.5f;
  for (const float r : tube.radii) EXPECT_EQ(r, radius);
  // The rounded end touches the nozzle's disc; the pipe leaves along the jet's axis.
  EXPECT_LT((tube.points[0] + radius * d - Vector3f(1, 0, 4)).norm(), 1e-5f);
  EXPECT_GT((tube.points[1] - tube.points[0]).normalized().dot(-d), 0.99999f);
  EXPECT_GE(tube.points[1].z(), 4.0f + 2.0f * radius - 1e-4f);  // two radii above the rim
  EXPECT_NEAR(tube.points[2].z() - tube.points[1].z(), kp::kFaucetRise, 1e-4f);
  EXPECT_EQ(set.material.type, kr::MaterialType::Mirror);
  EXPECT_EQ(kp::makeRenderScene(scene, 0.0).curves.size(), 1u);
  EXPECT_TRUE(kp::makeRenderScene(faucetScene(false), 0.0).curves.empty());
}

TEST(Faucets, ThePipeIsDrawnAboveTheNozzleOnlyWhenEnabled) {
  // The point on the pipe's axis 1.5 m back from its mouth, and 1.5 m to its side (sky).
  const Vector3f d = Vector3f(-0.5f, 0, -1).normalized();
  const Vector3f onPipe = Vector3f(1, 0, 4) - 1.5f * d, beside = onPipe + Vector3f(1.5f, 0, 0);
  for (const bool enabled : {true, false}) {
    const kp::Scene scene = faucetScene(enabled);
    const kr::Image image = kr::renderFrame(kp::makeRenderScene(scene, 0.0), scene.render.settings);
    const Eigen::Vector2i on = project(scene.render.camera, scene.render.settings, onPipe);
    const Eigen::Vector2i off = project(scene.render.camera, scene.render.settings, beside);
    EXPECT_EQ(image.at(on.x(), on.y())[3], enabled ? 1.0f : 0.0f) << "enabled " << enabled;
    EXPECT_EQ(image.at(off.x(), off.y())[3], 0.0f) << "enabled " << enabled;
  }
}

// Static geometry (render/scene.h staticMeshes): built once by a Renderer and kept while equal,
// rebuilt when it changes, and every frame exactly the image a fresh renderer gives.
namespace {

// A wall in the plane y = 1 (facing the camera at y = -6) and a glass sphere in front of it.
kr::RenderScene staticWallScene(const kr::TriangleMesh& wall, float sphereX) {
  kr::RenderScene scene;
  kr::Material checker;
  checker.checkerSize = 0.5f;
  checker.albedoB = {0.2f, 0.3f, 0.1f};
  scene.staticMeshes.push_back({&wall, checker, 7});
  kr::Material glass;
  glass.type = kr::MaterialType::Dielectric;
  glass.absorption = {0.3f, 0.1f, 0.05f};
  scene.spheres.push_back({{{sphereX, -0.5f, 0.8f}}, {}, 0.6f, glass});
  scene.camera.position = {0.5f, -6, 2.5f};
  scene.camera.lookAt = {0, 0, 0.8f};
  scene.sun.direction = {0.3f, 0.8f, -1.0f};
  return scene;
}

kr::TriangleMesh wallMesh(float height) {
  kr::TriangleMesh wall;
  wall.positions = {{-3, 1, 0}, {3, 1, 0}, {3, 1, height}, {-3, 1, height}};
  wall.triangles = {{0, 2, 1}, {0, 3, 2}};  // facing -y
  return wall;
}

}  // namespace

TEST(StaticGeometry, IsBuiltOnceAndRendersAsTheSameMeshRebuiltEveryFrameWould) {
  // Three frames of a moving sphere before a static wall, by one Renderer: the wall's geometry is
  // made by the first frame only, and each frame is bit for bit the image of the same scene with
  // the wall among the moving meshes, rendered by a fresh renderer.
  const kr::TriangleMesh wall = wallMesh(3.0f);
  const kr::RenderSettings settings = renderSettings(40, 30, 3, 6);
  kr::Renderer renderer;
  for (int frame = 0; frame < 3; ++frame) {
    const kr::RenderScene scene = staticWallScene(wall, -1.0f + 0.8f * float(frame));
    kr::RenderStats stats;
    const kr::Image image = renderer.render(scene, settings, &stats);
    EXPECT_EQ(renderer.staticBuilds(), 1) << "frame " << frame;
    EXPECT_EQ(stats.staticBuilt, frame == 0) << "frame " << frame;
    kr::RenderScene moving = scene;
    moving.meshes = moving.staticMeshes;
    moving.staticMeshes.clear();
    EXPECT_TRUE(image == kr::renderFrame(moving, settings)) << "frame " << frame;
    if (frame == 0) {
      EXPECT_TRUE(image == kr::renderFrame(scene, settings));
    }
  }
}

TEST(StaticGeometry, AChangedStaticMeshOrSkyIsRebuiltNotReused) {
  // The static part compared by value: another wall (same pointer, other vertices), then another
  // material, each rebuild it; another sky rebuilds the environment's sampler. Each frame is the
  // image a fresh renderer gives, and differs from the frame before it.
  kr::TriangleMesh wall = wallMesh(3.0f);
  kr::RenderSettings settings = renderSettings(40, 30, 3, 6);
  kr::Renderer renderer;
  kr::RenderScene scene = staticWallScene(wall, 0.0f);
  kr::Image before = renderer.render(scene, settings);
  const auto next = [&](int builds, const char* what) {
    const kr::Image image = renderer.render(scene, settings);
    EXPECT_EQ(renderer.staticBuilds(), builds) << what;
    EXPECT_TRUE(image == kr::renderFrame(scene, settings)) << what;
    EXPECT_FALSE(image == before) << what << " changed nothing";
    before = image;
  };
  wall = wallMesh(1.5f);
  next(2, "a lower wall");
  scene.staticMeshes[0].material.albedo = {0.9f, 0.2f, 0.2f};
  next(3, "a red wall");
  scene.environment.zenith = {0.9f, 0.5f, 0.1f};
  next(3, "an orange sky");
  scene.ground.normal = {0.05f, 0.0f, 1.0f};  // the sampler leaves out the sky below the ground
  next(3, "a tilted ground");
}

TEST(StaticGeometry, CameraKeysThatMoveTheEyePastATankWallRebuildItAndClipPlanesApply) {
  // The tiny dam break's tank (container [0,16] x [0,5] x [0,10], walls 4 m high) drawn by the
  // render stage's Renderer over camera keys that bring the eye from in front of the wall y = 0
  // (not drawn: seen from outside) to inside the tank (drawn): the static part is rebuilt when,
  // and only when, the walls drawn change; a clip plane added later cuts the kept walls. Each
  // frame is the image a fresh renderer gives.
  kp::Scene scene = kp::loadScene(kurage::test::sourceDir() / "tests/scenes/tiny_dam_break.json");
  scene.render.tank.enabled = true;
  scene.render.tank.height = 4.0f;
  scene.render.settings = renderSettings(48, 32, 2, 4);
  scene.render.cameraKeys = {{0.0, {8, -22, 12}, {8, 2.5f, 2}, 50.0f},
                             {1.0, {8, -18, 12}, {8, 2.5f, 2}, 50.0f},
                             {2.0, {8, 2, 12}, {8, 2.5f, 2}, 90.0f}};
  kr::Renderer renderer;
  kr::Image previous;
  const auto frame = [&](double time, int builds, const char* what) {
    const kr::RenderScene view = kp::makeRenderScene(scene, time);
    const kr::Image image = renderer.render(view, scene.render.settings);
    EXPECT_EQ(renderer.staticBuilds(), builds) << what;
    EXPECT_TRUE(image == kr::renderFrame(view, scene.render.settings)) << what;
    EXPECT_FALSE(image == previous) << what << " changed nothing";
    previous = image;
    return view.staticMeshes.at(0).mesh->triangles.size();
  };
  EXPECT_EQ(frame(0.0, 1, "t = 0"), 6u);
  EXPECT_EQ(frame(0.5, 1, "t = 0.5: the camera moved, the walls did not"), 6u);
  EXPECT_EQ(frame(2.0, 2, "t = 2: inside the tank, the front wall is drawn"), 8u);
  scene.render.clip = {true, {8, 2.5f, 2}, {1, 0, 0}};
  EXPECT_EQ(frame(2.0, 2, "t = 2 with the half x > 8 clipped"), 8u);
}
