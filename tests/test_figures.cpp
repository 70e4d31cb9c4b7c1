// `kurage figures` (pipeline/figures/figures.h): the tiny set writes every figure, each with
// something in its stills and its plot's data drawn; bad arguments are usage errors naming the
// argument; the panels compose as the layout says; a framed view holds its box.
#include "pipeline/figures/figures.h"
#include "pipeline/io/files.h"
#include "render/image.h"

#include "test_util.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>

namespace kurage::pipeline {
namespace {

namespace fs = std::filesystem;
using test::TempDir;

// The variance of the sRGB-encoded grey of the rows [y0, y1).
double greyVariance(const render::Image& image, int y0, int y1) {
  double sum = 0.0, sum2 = 0.0;
  long n = 0;
  for (int y = y0; y < y1; ++y)
    for (int x = 0; x < image.width(); ++x) {
      const Eigen::Vector4f& p = image.at(x, y);
      const double g = (render::linearToSrgb(p.x()) + render::linearToSrgb(p.y()) + render::linearToSrgb(p.z())) / 3.0;
      sum += g;
      sum2 += g * g;
      ++n;
    }
  const double mean = sum / double(n);
  return sum2 / double(n) - mean * mean;
}

// Pixels of the plots' force colour (#b03061): the curve was drawn.
int forcePixels(const render::Image& image) {
  int count = 0;
  for (int y = 0; y < image.height(); ++y)
    for (int x = 0; x < image.width(); ++x) {
      const Eigen::Vector4f& p = image.at(x, y);
      const float r = render::linearToSrgb(p.x()), g = render::linearToSrgb(p.y()), b = render::linearToSrgb(p.z());
      count += std::abs(r - 0.69f) < 0.08f && std::abs(g - 0.19f) < 0.08f && std::abs(b - 0.38f) < 0.08f;
    }
  return count;
}

TEST(Figures, TinySetWritesEveryFigureWithStillsAndPlottedData) {
  const TempDir dir;
  const fs::path out = dir.path() / "figures", log = dir.path() / "log.txt";
  ASSERT_EQ(test::runKurage("figures " + out.string() + " --quality tiny --threads 2 --scenes " +
                                (test::sourceDir() / "scenes").string(),
                            log),
            0)
      << readText(log);
  for (const char* name : {"fig2_membrane.png", "fig3_box.png", "fig5_jellyfish.png"}) {
    SCOPED_TRACE(name);
    const render::Image image = render::readPng(out / name);
    ASSERT_GT(image.height(), 8);
    // The stills (the top quarter: the first row of panels) are pictures, not a flat colour.
    EXPECT_GT(greyVariance(image, 0, image.height() / 4), 1e-4);
  }
  for (const char* name : {"fig3", "fig5"}) {
    SCOPED_TRACE(name);
    for (const char* ext : {".png", ".svg", ".pdf", ".gp"})
      EXPECT_GT(fs::file_size(out / (std::string(name) + "_force" + ext)), 100u) << ext;
    // The composite holds the plot, and the plot its curve and the stills' numbered markers.
    EXPECT_GT(forcePixels(render::readPng(out / (std::string(name) + "_force.png"))), 20);
    EXPECT_GT(forcePixels(render::readPng(out / (std::string(name) + (name == std::string("fig3") ? "_box.png" : "_jellyfish.png")))), 20);
    const std::string gp = readText(out / (std::string(name) + "_force.gp"));
    const size_t block = gp.find("$series0 << EOD\n");
    ASSERT_NE(block, std::string::npos);
    const std::string data = gp.substr(block + 16, gp.find("EOD\n", block + 16) - block - 16);
    EXPECT_GE(std::count(data.begin(), data.end(), '\n'), 6) << data;
    EXPECT_NE(gp.find("\"1\""), std::string::npos);  // marker 1 labelled
  }
  const nlohmann::json record = nlohmann::json::parse(readText(out / "figures.json"));
  EXPECT_EQ(record.at("quality"), "tiny");
  EXPECT_EQ(record.at("render").at("integrator"), "whitted");
  for (const char* name : {"fig2", "fig3", "fig5"}) EXPECT_TRUE(record.at("figures").contains(name)) << name;
  EXPECT_EQ(record["figures"]["fig3"]["moments_s"].size(), 2u);
}

TEST(Figures, BadArgumentsExitTwoNamingTheArgument) {
  const TempDir dir;
  const fs::path log = dir.path() / "log.txt", out = dir.path() / "out";
  const std::pair<std::string, std::string> cases[] = {
      {"figures " + out.string() + " --quality huge", "--quality: expected tiny, preview or final, got huge"},
      {"figures " + out.string() + " --only fig4", "--only: expected fig2, fig3 or fig5, got fig4"},
      {"figures", "expected one output folder DIR"},
      {"figures " + out.string() + " --scenes " + (dir.path() / "none").string(), "--scenes: folder"},
      {"figures " + out.string() + " --bogus", "--bogus"},
  };
  for (const auto& [arguments, message] : cases) {
    SCOPED_TRACE(arguments);
    EXPECT_EQ(test::runKurage(arguments, log), 2);
    EXPECT_NE(readText(log).find(message), std::string::npos) << readText(log);
  }
  EXPECT_FALSE(fs::exists(out));  // nothing written
  EXPECT_EQ(test::runKurage("figures --help", log), 0);
  EXPECT_NE(readText(log).find("fig5_jellyfish.png"), std::string::npos);
}

// The path tracer at a figure's samples leaves grain on the translucent bodies and the far floor;
// every level renders noise-free, with filtered checkers, by the whitted integrator.
TEST(Figures, EveryLevelRendersWithTheWhittedIntegrator) {
  for (FigureQuality q : {FigureQuality::Tiny, FigureQuality::Preview, FigureQuality::Final}) {
    SCOPED_TRACE(figureQualityName(q));
    EXPECT_EQ(figureLevel(q).integrator, render::IntegratorType::Whitted);
  }
  EXPECT_LT(figureLevel(FigureQuality::Preview).samples, figureLevel(FigureQuality::Final).samples);
}

TEST(Figures, PanelsSitSideBySideAndCentredBelow) {
  const render::Image red(2, 3, {1, 0, 0, 1}), green(4, 1, {0, 1, 0, 1});
  const render::Image row = besideEachOther({red, green}, 1, {0, 0, 0, 1});
  ASSERT_EQ(row.width(), 7);
  ASSERT_EQ(row.height(), 3);
  EXPECT_EQ(row.at(1, 2), red.at(0, 0));
  EXPECT_EQ(row.at(2, 0), Eigen::Vector4f(0, 0, 0, 1));  // the gap
  EXPECT_EQ(row.at(3, 0), green.at(0, 0));
  EXPECT_EQ(row.at(3, 1), Eigen::Vector4f(0, 0, 0, 1));  // below the shorter panel
  const render::Image column = aboveEachOther({green, red}, 2, {0, 0, 0, 1});
  ASSERT_EQ(column.width(), 4);
  ASSERT_EQ(column.height(), 6);
  EXPECT_EQ(column.at(0, 0), green.at(0, 0));
  EXPECT_EQ(column.at(1, 3), red.at(0, 0));  // centred: columns 1-2
  EXPECT_EQ(column.at(0, 3), Eigen::Vector4f(0, 0, 0, 1));
  EXPECT_EQ(column.at(3, 5), Eigen::Vector4f(0, 0, 0, 1));
}

TEST(Figures, AFramedViewHoldsItsBox) {
  const Eigen::Vector3f lo(2, 5, 1), hi(12, 5, 21);
  for (float aspect : {0.5f, 2.0f}) {
    const FramedView v = frameFromFront(lo, hi, aspect, 45.0f, 0.0f);
    EXPECT_FLOAT_EQ(v.lookAt.x(), 7.0f);
    EXPECT_FLOAT_EQ(v.lookAt.z(), 11.0f);
    const float d = v.lookAt.y() - v.position.y(), t = std::tan(22.5f * 3.14159265f / 180.0f);
    // Both half extents fit, one of them exactly.
    EXPECT_LE(10.0f, d * t + 1e-3f);
    EXPECT_LE(5.0f, d * t * aspect + 1e-3f);
    EXPECT_NEAR(std::min(d * t - 10.0f, d * t * aspect - 5.0f), 0.0f, 1e-3f);
  }
}

}  // namespace
}  // namespace kurage::pipeline
