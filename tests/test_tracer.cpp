// Tracer tests with analytic answers: sky gradient, Lambert radiance under a sun, hard and soft
// shadows, a rectangular light's irradiance, smooth normals, clip plane, alpha, camera keys, and
// thread-count independence. The furnace and refraction checks are in test_render_validation.cpp.
#include "render/tracer.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <Eigen/Geometry>

#include <cmath>
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
  scene.sun.direction = {0, 0, -1};
  scene.sun.irradiance = {kPi, kPi, kPi};
  scene.sun.angularDiameterDegrees = 2.0f;
  scene.ground.enabled = true;
  scene.ground.checkerSize = 0.0f;
  scene.ground.albedoA = {1, 1, 1};
  scene.camera.position = {0, -2, 5};
  scene.camera.lookAt = {0, 0, 0};
  kr::RenderSettings settings;
  settings.width = 1;
  settings.height = 1;
  settings.samplesPerPixel = 2048;
  settings.maxDepth = 1;
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
  scene.ground.enabled = true;
  scene.ground.checkerSize = 0.0f;
  scene.ground.albedoA = {1, 1, 1};
  scene.camera.position = {0, -4, 1};
  scene.camera.lookAt = {0, 0, 0};
  scene.camera.verticalFovDegrees = 0.5f;
  kr::RenderSettings settings;
  settings.width = 3;
  settings.height = 3;
  settings.samplesPerPixel = 1024;
  settings.maxDepth = 1;
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
  scene.sun.direction = {0, 1, 0};  // along the view direction: shading = n . (0, -1, 0)
  scene.sun.irradiance = {kPi, kPi, kPi};
  scene.sun.angularDiameterDegrees = 0.0f;
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

TEST(Tracer, TransmissiveShadowsPassWaterWithFresnelAndAbsorption) {
  // A glass slab (n = 1.5, absorption 0.5 / m, 1 m thick, z in [1, 2]) over a white ground, a
  // point sun straight down with E = pi, black sky, direct light only, and the camera below the
  // slab: the ground under the slab gets E T / pi with T = (1 - F0)^2 exp(-0.5), F0 = 0.04
  // (normal incidence in and out; no noise). The ray offset against self-intersection (1e-4 of
  // the scene's size, 0.5 mm here) shortens the path inside by up to 1 mm: tolerance 5e-4.
  // Without transmissive shadows the ground under the slab is black.
  kr::TriangleMesh slab;
  const float s = 5.0f;
  slab.positions = {{-s, -s, 1}, {s, -s, 1}, {s, s, 1}, {-s, s, 1}, {-s, -s, 2}, {s, -s, 2}, {s, s, 2}, {-s, s, 2}};
  slab.triangles = {{0, 2, 1}, {0, 3, 2}, {4, 5, 6}, {4, 6, 7}, {0, 1, 5}, {0, 5, 4},
                    {1, 2, 6}, {1, 6, 5}, {2, 3, 7}, {2, 7, 6}, {3, 0, 4}, {3, 4, 7}};
  kr::Material glass;
  glass.type = kr::MaterialType::Dielectric;
  glass.ior = 1.5f;
  glass.absorption = {0.5f, 0.5f, 0.5f};
  kr::RenderScene scene = darkScene();
  scene.meshes.push_back({&slab, glass});
  scene.sun.direction = {0, 0, -1};
  scene.sun.irradiance = {kPi, kPi, kPi};
  scene.sun.angularDiameterDegrees = 0.0f;
  scene.ground.enabled = true;
  scene.ground.checkerSize = 0.0f;
  scene.ground.albedoA = {1, 1, 1};
  scene.camera.position = {0, -2, 0.5f};
  scene.camera.lookAt = {0, 0, 0};
  kr::RenderSettings settings;
  settings.width = 3;
  settings.height = 3;
  settings.samplesPerPixel = 4;
  settings.maxDepth = 1;
  const float expected = 0.96f * 0.96f * std::exp(-0.5f);
  EXPECT_NEAR(kr::renderFrame(scene, settings).at(1, 1).x(), expected, 5e-4f);
  settings.transmissiveShadows = false;
  EXPECT_NEAR(kr::renderFrame(scene, settings).at(1, 1).x(), 0.0f, 1e-6f);
}
