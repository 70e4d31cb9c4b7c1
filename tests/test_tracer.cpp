// Tracer tests with analytic answers: sky gradient, Lambert radiance of a lit triangle, the
// shadow of a quad on the ground (lit minus shadowed = albedo * radiance * cos), thread-count
// independence, and smooth (interpolated) normals.
#include "render/tracer.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <Eigen/Geometry>

#include <cmath>
#include <numbers>

namespace kr = kurage::render;
using Eigen::Vector3f;

namespace {

// Pixel (column, row) whose footprint contains the image of world point p, for the pinhole
// camera of tracer.h (vertical FOV, look-at, row 0 on top).
Eigen::Vector2i project(const kr::Camera& camera, const kr::RenderSettings& s, const Vector3f& p) {
  const Vector3f forward = (camera.lookAt - camera.position).normalized();
  const Vector3f right = forward.cross(camera.up).normalized();
  const Vector3f up = right.cross(forward);
  const Vector3f d = p - camera.position;
  const float tanHalf = std::tan(0.5f * camera.verticalFovDegrees * std::numbers::pi_v<float> / 180.0f);
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
  const float tanHalf = std::tan(0.5f * camera.verticalFovDegrees * std::numbers::pi_v<float> / 180.0f);
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

kr::Camera cameraLookingAlongY() {
  kr::Camera camera;
  camera.position = {0, -5, 0};
  camera.lookAt = {0, 0, 0};
  camera.up = {0, 0, 1};
  camera.verticalFovDegrees = 45.0f;
  return camera;
}

}  // namespace

TEST(Tracer, EmptySceneShowsSkyGradient) {
  kr::Camera camera;
  camera.position = {0, 0, 1};
  camera.lookAt = {0, 10, 1};  // horizontal
  kr::Ground ground;
  ground.enabled = false;
  kr::RenderSettings settings;
  settings.width = 24;
  settings.height = 32;
  const kr::Image image = kr::renderFrame({}, camera, {}, ground, settings);
  ASSERT_EQ(image.width(), 24);
  ASSERT_EQ(image.height(), 32);
  const int cx = settings.width / 2;
  const auto toZenith = [&](int y) { return (rgb(image, cx, y) - settings.skyZenith).norm(); };
  EXPECT_LT(toZenith(0), toZenith(settings.height - 1) - 0.1f);
  for (int y = 1; y < settings.height; ++y) EXPECT_LE(toZenith(y - 1), toZenith(y) + 1e-6f) << "row " << y;
  // Below the horizon the sky is the horizon colour; everything is opaque.
  EXPECT_LT((rgb(image, cx, settings.height - 1) - settings.skyHorizon).norm(), 1e-5f);
  EXPECT_EQ(image.at(0, 0)[3], 1.0f);
}

TEST(Tracer, FacingTriangleHasAlbedoTimesRadiance) {
  const kr::TriangleMesh mesh = bigTriangle(100.0f);
  kr::SceneObject object{&mesh, {}};
  object.material.albedo = {0.3f, 0.6f, 0.9f};
  kr::DirectionalLight light;
  light.direction = {0, 3, 0};  // along the view direction, not normalised
  light.radiance = {2.0f, 1.5f, 1.0f};
  kr::Ground ground;
  ground.enabled = false;
  kr::RenderSettings settings;
  settings.width = 33;
  settings.height = 21;
  settings.ambient = 0.0f;
  const kr::Image image = kr::renderFrame({object}, cameraLookingAlongY(), light, ground, settings);
  const Vector3f expected = object.material.albedo.cwiseProduct(light.radiance);
  const Vector3f centre = rgb(image, settings.width / 2, settings.height / 2);
  EXPECT_TRUE(centre.isApprox(expected, 1e-5f)) << centre.transpose();
  EXPECT_NEAR((centre - expected).cwiseAbs().maxCoeff(), 0.0f, 1e-5f);

  // Lit from behind, the triangle gets no direct light (and with ambient 0 is black).
  light.direction = {0, -1, 0};
  const kr::Image back = kr::renderFrame({object}, cameraLookingAlongY(), light, ground, settings);
  EXPECT_NEAR(rgb(back, settings.width / 2, settings.height / 2).norm(), 0.0f, 1e-6f);
}

TEST(Tracer, QuadCastsShadowOnGround) {
  // Quad at height 1 over [-0.5, 0.5]^2; light travelling along (1, 0, -1) puts its shadow on
  // the ground over x in [0.5, 1.5], y in [-0.5, 0.5].
  kr::TriangleMesh quad;
  quad.positions = {{-0.5f, -0.5f, 1}, {0.5f, -0.5f, 1}, {0.5f, 0.5f, 1}, {-0.5f, 0.5f, 1}};
  quad.triangles = {{0, 1, 2}, {0, 2, 3}};
  kr::DirectionalLight light;
  light.direction = {1, 0, -1};
  light.radiance = {2.0f, 2.0f, 2.0f};
  kr::Ground ground;
  ground.checkerSize = 0.0f;  // plain albedoA
  kr::Camera camera;
  camera.position = {0, -8, 6};
  camera.lookAt = {0.5f, 0, 0};
  kr::RenderSettings settings;
  settings.width = 160;
  settings.height = 120;

  const kr::Image image = kr::renderFrame({{&quad, {}}}, camera, light, ground, settings);
  const Eigen::Vector2i inShadow = project(camera, settings, {1.0f, 0.0f, 0.0f});
  const Eigen::Vector2i lit = project(camera, settings, {1.0f, 1.5f, 0.0f});
  const Eigen::Vector2i litLeft = project(camera, settings, {-1.5f, 0.0f, 0.0f});
  // The point (1, 0, 0) is not hidden by the quad itself: the camera ray meets z = 1 at
  // (0.83, -1.33), outside the quad.
  const Vector3f expectedDifference = ground.albedoA * 2.0f * std::sqrt(0.5f);  // albedo * E * cos 45
  const Vector3f shadow = rgb(image, inShadow.x(), inShadow.y());
  EXPECT_LT((rgb(image, lit.x(), lit.y()) - shadow - expectedDifference).norm(), 1e-4f);
  EXPECT_LT((rgb(image, litLeft.x(), litLeft.y()) - shadow - expectedDifference).norm(), 1e-4f);
  // Without the quad, the same ground point is lit.
  const kr::Image empty = kr::renderFrame({}, camera, light, ground, settings);
  EXPECT_LT((rgb(empty, inShadow.x(), inShadow.y()) - rgb(image, lit.x(), lit.y())).norm(), 1e-5f);
}

TEST(Tracer, ImageDoesNotDependOnThreadCount) {
  kr::TriangleMesh mesh = bigTriangle(1.0f);
  mesh.normals = {Vector3f(-1, -1, 0).normalized(), Vector3f(1, -1, 0).normalized(), {0, -1, 0}};
  kr::Camera camera;
  camera.position = {1, -6, 3};
  camera.lookAt = {0, 0, 0};
  kr::RenderSettings settings;
  settings.width = 97;  // not a multiple of the tile size
  settings.height = 61;
  settings.samplesPerPixel = 5;
  const auto render = [&](int threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<size_t>(threads));
    return kr::renderFrame({{&mesh, {}}}, camera, {}, {}, settings);
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
}

TEST(Tracer, VertexNormalsAreInterpolatedAcrossFlatTriangle) {
  kr::TriangleMesh flat = bigTriangle(3.0f);
  kr::TriangleMesh smooth = flat;
  smooth.normals = {Vector3f(-2, -1, 0).normalized(), Vector3f(2, -1, 0).normalized(), {0, -1, 0}};
  kr::DirectionalLight light;
  light.direction = {0, 1, 0};  // along the view direction: shading = n . (0, -1, 0)
  light.radiance = {1, 1, 1};
  kr::Ground ground;
  ground.enabled = false;
  kr::RenderSettings settings;
  settings.width = 64;
  settings.height = 64;
  settings.ambient = 0.0f;
  const kr::Camera camera = cameraLookingAlongY();
  kr::SceneObject object{&flat, {}};
  object.material.albedo = {1, 1, 1};
  const kr::Image flatImage = kr::renderFrame({object}, camera, light, ground, settings);
  object.mesh = &smooth;
  const kr::Image smoothImage = kr::renderFrame({object}, camera, light, ground, settings);

  // Pixels in the lower half of the triangle, left of centre, at the centre, right of centre.
  const int row = 40;
  for (int x : {13, 32, 50}) {
    const Vector3f p = pixelCentreOnPlaneY0(camera, settings, x, row);
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
  EXPECT_NEAR(smoothImage.at(13, row).x(), smoothImage.at(50, row).x(), 1e-3f);  // mirror symmetric
}
