// Preview (OSMesa sphere impostors): spheres land where the pinhole camera projects them, with
// the colour they were given; empty input is background only; frames are deterministic; a
// nearer sphere hides a farther one.
#include "render/preview.h"
#include "test_util.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>

namespace kurage::render {
namespace {

Camera testCamera() {
  Camera camera;
  camera.position = Eigen::Vector3f(1.0f, -12.0f, 4.0f);
  camera.lookAt = Eigen::Vector3f(0.5f, 0.0f, 1.0f);
  camera.up = Eigen::Vector3f(0, 0, 1);
  camera.verticalFovDegrees = 40.0f;
  return camera;
}

PreviewSettings testSettings() {
  PreviewSettings s;
  s.width = 160;
  s.height = 96;
  s.background = Eigen::Vector3f(0.5f, 0.5f, 0.5f);
  // A light from the camera's side: the visible hemisphere is lit.
  s.lightDirection = testCamera().lookAt - testCamera().position;
  return s;
}

bool isBackground(const Image& image, int x, int y, const Eigen::Vector3f& background) {
  const Eigen::Vector4f p = image.at(x, y);
  return std::abs(linearToSrgb(p.x()) - linearToSrgb(background.x())) < 1.5f / 255 &&
         std::abs(linearToSrgb(p.y()) - linearToSrgb(background.y())) < 1.5f / 255 &&
         std::abs(linearToSrgb(p.z()) - linearToSrgb(background.z())) < 1.5f / 255;
}

// Which of red, green, blue dominates a pixel (-1 for none by a clear margin).
int dominantChannel(const Eigen::Vector4f& p) {
  for (int c = 0; c < 3; ++c)
    if (p[c] > 2.0f * p[(c + 1) % 3] && p[c] > 2.0f * p[(c + 2) % 3] && p[c] > 0.02f) return c;
  return -1;
}

// Three spheres of different colours at known places.
PreviewSpheres knownSpheres() {
  PreviewSpheres s;
  s.centres = {{-2.0f, 0.0f, 1.0f}, {1.0f, 1.0f, 2.5f}, {3.0f, -1.0f, 0.0f}};
  s.radii = {0.6f, 0.4f, 0.5f};
  s.colours = {{0.9f, 0.05f, 0.05f}, {0.05f, 0.9f, 0.05f}, {0.05f, 0.05f, 0.9f}};
  return s;
}

TEST(Preview, SpheresAppearWhereTheCameraProjectsThemWithTheirColours) {
  PreviewRenderer renderer;
  const Camera camera = testCamera();
  const PreviewSettings settings = testSettings();
  const PreviewSpheres spheres = knownSpheres();
  const Image image = renderer.render(spheres, camera, settings);
  ASSERT_EQ(image.width(), settings.width);
  ASSERT_EQ(image.height(), settings.height);

  // Pixels whose centre projects within 0.6 of a sphere's projected radius are that sphere's
  // colour; those beyond 1.6 projected radii from every sphere are background.
  const float pixelsPerRadian = 0.5f * float(settings.height) / std::tan(0.5f * camera.verticalFovDegrees * float(M_PI) / 180.0f);
  std::vector<Eigen::Vector3f> projected;
  std::vector<float> projectedRadius;
  for (size_t i = 0; i < spheres.centres.size(); ++i) {
    projected.push_back(CameraRays(camera, settings.width, settings.height).project(spheres.centres[i]));
    ASSERT_GT(projected.back().z(), 0.0f);
    projectedRadius.push_back(spheres.radii[i] / projected.back().z() * pixelsPerRadian);
    ASSERT_GT(projectedRadius.back(), 2.0f);  // big enough to test
  }
  size_t inside = 0, outside = 0;
  for (int y = 0; y < settings.height; ++y)
    for (int x = 0; x < settings.width; ++x) {
      bool nearAny = false;
      for (size_t i = 0; i < projected.size(); ++i) {
        const float d = std::hypot(x + 0.5f - projected[i].x(), y + 0.5f - projected[i].y());
        if (d < 0.6f * projectedRadius[i]) {
          EXPECT_EQ(dominantChannel(image.at(x, y)), int(i)) << "pixel " << x << " " << y << " sphere " << i;
          ++inside;
        }
        nearAny = nearAny || d < 1.6f * projectedRadius[i];
      }
      if (!nearAny) {
        EXPECT_TRUE(isBackground(image, x, y, settings.background)) << "pixel " << x << " " << y;
        ++outside;
      }
    }
  EXPECT_GT(inside, 30u);
  EXPECT_GT(outside, 1000u);
  // Lambert shading: the lit centre is brighter than the rim.
  const Eigen::Vector3f c = projected[0];
  const Eigen::Vector4f centre = image.at(int(c.x()), int(c.y()));
  const Eigen::Vector4f rim = image.at(int(c.x() - 0.85f * projectedRadius[0]), int(c.y()));
  EXPECT_GT(centre.x(), rim.x());
}

TEST(Preview, EmptyInputGivesBackgroundOnly) {
  PreviewRenderer renderer;
  const PreviewSettings settings = testSettings();
  const Image image = renderer.render(PreviewSpheres{}, testCamera(), settings);
  for (int y = 0; y < image.height(); ++y)
    for (int x = 0; x < image.width(); ++x) ASSERT_TRUE(isBackground(image, x, y, settings.background)) << x << " " << y;
}

TEST(Preview, FramesAreDeterministicAndSizesCanChange) {
  PreviewSpheres spheres;
  for (int i = 0; i < 500; ++i)  // a jumble of overlapping spheres
    spheres.centres.emplace_back(float(i % 10) * 0.4f - 2.0f, float((i / 10) % 5) * 0.4f, float(i / 50) * 0.3f);
  spheres.radii.assign(spheres.centres.size(), 0.3f);
  for (size_t i = 0; i < spheres.centres.size(); ++i) spheres.colours.emplace_back(0.1f * float(i % 10), 0.3f, 0.6f);
  PreviewRenderer renderer;
  const Image a = renderer.render(spheres, testCamera(), testSettings());
  PreviewSettings bigger = testSettings();
  bigger.width = 200;
  const Image b = renderer.render(spheres, testCamera(), bigger);
  EXPECT_EQ(b.width(), 200);
  const Image c = renderer.render(spheres, testCamera(), testSettings());
  PreviewRenderer other;
  const Image d = other.render(spheres, testCamera(), testSettings());
  size_t differing = 0, coloured = 0;
  for (int y = 0; y < a.height(); ++y)
    for (int x = 0; x < a.width(); ++x) {
      differing += a.at(x, y) != c.at(x, y) || a.at(x, y) != d.at(x, y);
      coloured += !isBackground(a, x, y, testSettings().background);
    }
  EXPECT_EQ(differing, 0u);
  EXPECT_GT(coloured, 500u);
}

TEST(Preview, NearerSphereHidesFartherOne) {
  Camera camera = testCamera();
  const Eigen::Vector3f forward = (camera.lookAt - camera.position).normalized();
  PreviewSpheres spheres;
  // Far red sphere drawn last: depth testing, not drawing order, must decide.
  spheres.centres = {camera.position + 8.0f * forward, camera.position + 14.0f * forward};
  spheres.radii = {0.5f, 1.5f};
  spheres.colours = {{0.05f, 0.05f, 0.9f}, {0.9f, 0.05f, 0.05f}};
  PreviewRenderer renderer;
  const PreviewSettings settings = testSettings();
  const Image image = renderer.render(spheres, camera, settings);
  const Eigen::Vector3f c = CameraRays(camera, settings.width, settings.height).project(spheres.centres[0]);
  EXPECT_EQ(dominantChannel(image.at(int(c.x()), int(c.y()))), 2);
  std::swap(spheres.centres[0], spheres.centres[1]);
  std::swap(spheres.radii[0], spheres.radii[1]);
  std::swap(spheres.colours[0], spheres.colours[1]);
  EXPECT_EQ(dominantChannel(renderer.render(spheres, camera, settings).at(int(c.x()), int(c.y()))), 2);
}

TEST(Preview, RejectsMismatchedInput) {
  PreviewRenderer renderer;
  PreviewSpheres spheres = knownSpheres();
  spheres.radii.pop_back();
  EXPECT_THROW(renderer.render(spheres, testCamera(), testSettings()), std::invalid_argument);
  Camera degenerate = testCamera();
  degenerate.lookAt = degenerate.position;
  EXPECT_THROW(renderer.render(knownSpheres(), degenerate, testSettings()), std::invalid_argument);
}

std::string readFile(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

TEST(PreviewCommand, DrawsEveryCachedFrameAndNamesTheMissingStage) {
  const test::TempDir dir;
  const std::string scene = (test::sourceDir() / "tests/scenes/tiny_dam_break.json").string();
  const std::filesystem::path out = dir.path() / "out", log = dir.path() / "log.txt";
  EXPECT_EQ(test::runKurage("preview " + scene + " -o " + out.string(), log), 1);
  EXPECT_NE(readFile(log).find("kurage sim"), std::string::npos) << readFile(log);

  ASSERT_EQ(test::runKurage("sim " + scene + " -o " + out.string(), log), 0) << readFile(log);
  ASSERT_EQ(test::runKurage("preview " + scene + " -o " + out.string() + " --width 80 --height 60 --color speed", log), 0)
      << readFile(log);
  for (int f = 0; f < 5; ++f) {  // the scene has 5 frames
    char name[16];
    std::snprintf(name, sizeof name, "%04d.png", f);
    const Image image = readPng(out / "preview" / name);
    EXPECT_EQ(image.width(), 80);
    EXPECT_EQ(image.height(), 60);
    // Spheres (any colour: by speed here) over a plain background, which fills the corners.
    const Eigen::Vector3f background = image.at(0, 0).head<3>();
    size_t coloured = 0;
    for (int y = 0; y < image.height(); ++y)
      for (int x = 0; x < image.width(); ++x) coloured += !isBackground(image, x, y, background);
    EXPECT_GT(coloured, 20u) << name;
    EXPECT_TRUE(isBackground(image, image.width() - 1, image.height() - 1, background)) << name;
  }
  const std::string printed = readFile(log);
  if (printed.find("ffmpeg is not on the PATH") == std::string::npos) {
    EXPECT_GT(std::filesystem::file_size(out / "preview.mp4"), 1000u) << printed;
    EXPECT_FALSE(std::filesystem::exists(out / "preview.mp4.tmp"));
  }
}

}  // namespace
}  // namespace kurage::render
