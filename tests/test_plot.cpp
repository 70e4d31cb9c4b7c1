// Plots: a known line lands on the expected pixels and nowhere else; log axes give decades equal
// lengths; ticks are nice numbers and labelled with the digits they need; the second y axis has
// its own scale; text draws dark pixels inside its box only; PNGs round-trip; bad data and empty
// plots still give a framed image.
#include "pipeline/io/image_file.h"
#include "render/plot.h"

#include "test_util.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace kurage::render {
namespace {

using kurage::test::TempDir;

const Eigen::Vector3f kRed(0.8f, 0.1f, 0.1f);

Eigen::Vector3f srgbAt(const Image& image, int x, int y) {
  const Eigen::Vector4f& p = image.at(x, y);
  return {linearToSrgb(p[0]), linearToSrgb(p[1]), linearToSrgb(p[2])};
}

bool near(const Eigen::Vector3f& a, const Eigen::Vector3f& b, float tolerance = 0.02f) {
  return (a - b).cwiseAbs().maxCoeff() <= tolerance;
}

bool isDark(const Image& image, int x, int y) { return srgbAt(image, x, y).maxCoeff() < 0.5f; }

// y = x on fixed axes [0, 1] x [0, 1], no grid, no legend.
Plot diagonalPlot() {
  Plot plot;
  plot.x.min = plot.y.min = 0.0;
  plot.x.max = plot.y.max = 1.0;
  plot.grid = false;
  PlotSeries line;
  line.x = line.y = {0.0, 0.5, 1.0};
  line.colour = kRed;
  plot.series.push_back(line);
  return plot;
}

TEST(Plot, LineLiesOnTheDiagonalAndNowhereElse) {
  const Plot plot = diagonalPlot();
  const PlotFrame f = plotFrame(plot);
  ASSERT_GT(f.right - f.left, 200);
  ASSERT_GT(f.bottom - f.top, 200);
  EXPECT_EQ(f.toPixel(0, 0), Eigen::Vector2d(f.left, f.bottom));
  EXPECT_EQ(f.toPixel(1, 1), Eigen::Vector2d(f.right, f.top));
  const Image image = renderPlot(plot);
  ASSERT_EQ(image.width(), plot.width);
  ASSERT_EQ(image.height(), plot.height);
  // Along each column away from the corners, the pixel nearest the line (under 0.5 px from it) has the series colour;
  // 8 px above and below (over 5.5 px from it) is background.
  int columns = 0, onLine = 0, offLine = 0;
  for (int x = f.left + 20; x <= f.right - 20; ++x, ++columns) {
    const double t = double(x - f.left) / (f.right - f.left);
    const int y = static_cast<int>(std::lround(f.toPixel(t, t).y()));
    onLine += near(srgbAt(image, x, y), kRed);
    offLine += near(srgbAt(image, x, y - 8), Eigen::Vector3f::Ones()) && near(srgbAt(image, x, y + 8), Eigen::Vector3f::Ones());
  }
  EXPECT_EQ(onLine, columns);
  EXPECT_EQ(offLine, columns);
  // Nowhere else: every pixel of about the series colour is within 2 px of the diagonal.
  const double w = f.right - f.left, h = f.bottom - f.top;
  for (int y = f.top; y <= f.bottom; ++y)
    for (int x = f.left; x <= f.right; ++x)
      if (near(srgbAt(image, x, y), kRed, 0.1f)) {
        const double distance = std::abs((x - f.left) * h - (f.bottom - y) * w) / std::hypot(w, h);
        ASSERT_LT(distance, 2.0) << x << "," << y;
      }
}

TEST(Plot, LogAxisGivesDecadesEqualLengths) {
  Plot plot;
  plot.x.log = true;
  plot.x.min = 0.5;
  plot.x.max = 2000.0;
  plot.y.min = 0.0;
  plot.y.max = 2.0;
  plot.grid = false;
  PlotSeries dots;
  dots.x = {1.0, 10.0, 100.0, 1000.0};
  dots.y = {1.0, 1.0, 1.0, 1.0};
  dots.lines = false;
  dots.markers = true;
  dots.colour = kRed;
  plot.series.push_back(dots);
  const PlotFrame f = plotFrame(plot);
  const Image image = renderPlot(plot);
  // The marker centres along the row of y = 1: the means of the runs of red pixels.
  const int row = static_cast<int>(std::lround(f.toPixel(1.0, 1.0).y()));
  std::vector<double> centres;
  for (int x = f.left, start = -1; x <= f.right + 1; ++x) {
    const bool red = x <= f.right && near(srgbAt(image, x, row), kRed, 0.1f);
    if (red && start < 0) start = x;
    if (!red && start >= 0) {
      centres.push_back(0.5 * (start + x - 1));
      start = -1;
    }
  }
  ASSERT_EQ(centres.size(), 4u);
  const double decade = (f.right - f.left) / std::log10(2000.0 / 0.5);
  for (size_t i = 0; i < 4; ++i) {
    EXPECT_NEAR(centres[i], f.toPixel(dots.x[i], 1.0).x(), 0.6);
    if (i > 0) {
      EXPECT_NEAR(centres[i] - centres[i - 1], decade, 1.0);
    }
  }
  EXPECT_NEAR(f.toPixel(10.0, 1.0).x() - f.toPixel(1.0, 1.0).x(), f.toPixel(1000.0, 1.0).x() - f.toPixel(100.0, 1.0).x(), 1e-9);
}

TEST(Plot, AutomaticRangeCoversTheDataWithAMargin) {
  Plot plot;
  PlotSeries s;
  s.x = {2.0, 4.0, 6.0};
  s.y = {-1.0, 3.0, 1.0};
  plot.series.push_back(s);
  const PlotFrame f = plotFrame(plot);
  EXPECT_NEAR(f.x.lo, 1.8, 1e-12);
  EXPECT_NEAR(f.x.hi, 6.2, 1e-12);
  EXPECT_NEAR(f.y.lo, -1.2, 1e-12);
  EXPECT_NEAR(f.y.hi, 3.2, 1e-12);
  EXPECT_FALSE(f.hasY2);
  plot.x.min = plot.x.max = 1.0;
  EXPECT_THROW(plotFrame(plot), std::invalid_argument);
  plot.x = PlotAxis{};
  plot.y.log = true;
  plot.y.min = -1.0;
  EXPECT_THROW(plotFrame(plot), std::invalid_argument);
  plot.y.min = std::numeric_limits<double>::quiet_NaN();
  // On a log axis the value -1 is skipped: the range comes from 1 and 3, in decades.
  const PlotFrame g = plotFrame(plot);
  const double margin = 0.05 * std::log10(3.0);
  EXPECT_NEAR(std::log10(g.y.lo), -margin, 1e-12);
  EXPECT_NEAR(std::log10(g.y.hi), std::log10(3.0) + margin, 1e-12);
  EXPECT_NEAR(g.x.lo, 3.9, 1e-12);  // only the points that can be drawn count for x too
}

TEST(Plot, SecondAxisHasItsOwnScale) {
  Plot plot;
  plot.grid = false;
  PlotSeries force, depth;
  force.x = depth.x = {0.0, 1.0, 2.0};
  force.y = {0.0, 5.0, 10.0};
  depth.y = {1000.0, 3000.0, 2000.0};
  depth.axis = 1;
  depth.colour = kRed;
  depth.lines = false;
  depth.markers = true;
  force.label = "force";
  depth.label = "depth";
  plot.y.label = "force (N)";
  plot.y2.label = "depth (m)";
  plot.series = {force, depth};
  const PlotFrame f = plotFrame(plot);
  ASSERT_TRUE(f.hasY2);
  EXPECT_LT(f.y.hi, 20.0);
  EXPECT_GT(f.y2.lo, 800.0);
  EXPECT_LT(f.y2.hi, 3200.0);
  EXPECT_LT(f.right, plot.width - 60);  // room for the right axis's labels
  const Image image = renderPlot(plot);
  const Eigen::Vector2d p = f.toPixel(1.0, 3000.0, 1);
  EXPECT_NEAR(p.y(), f.top + 1.0 / 22.0 * (f.bottom - f.top), 1e-9);  // range 900..3100
  EXPECT_TRUE(near(srgbAt(image, int(std::lround(p.x())), int(std::lround(p.y()))), kRed, 0.02f));
  // Right-axis tick labels: dark pixels right of the frame.
  int dark = 0;
  for (int y = f.top; y <= f.bottom; ++y)
    for (int x = f.right + 8; x < f.right + 40; ++x) dark += isDark(image, x, y);
  EXPECT_GT(dark, 50);
}

TEST(Ticks, NiceStepsInsideTheRange) {
  EXPECT_EQ(niceTicks(0.0, 1.0, 5), (std::vector<double>{0.0, 0.2, 0.4, 0.6, 0.8, 1.0}));
  EXPECT_EQ(niceTicks(0.0, 1.0, 10), (std::vector<double>{0.0, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0}));
  EXPECT_EQ(niceTicks(-3.7, 12.2, 5), (std::vector<double>{0.0, 5.0, 10.0}));
  EXPECT_EQ(niceTicks(-3.7, 12.2, 8), (std::vector<double>{-2.0, 0.0, 2.0, 4.0, 6.0, 8.0, 10.0, 12.0}));
  EXPECT_EQ(niceTicks(1.0e5, 3.2e5, 4), (std::vector<double>{1.0e5, 1.5e5, 2.0e5, 2.5e5, 3.0e5}));
  EXPECT_EQ(niceTicks(0.0031, 0.0049, 4), (std::vector<double>{0.0035, 0.004, 0.0045}));
  EXPECT_EQ(niceTicks(-1.0, -0.5, 5), (std::vector<double>{-1.0, -0.9, -0.8, -0.7, -0.6, -0.5}));
  EXPECT_EQ(niceTicks(2.0, 2.0, 5), std::vector<double>{2.0});
  EXPECT_TRUE(niceTicks(0.0, std::numeric_limits<double>::infinity(), 5).empty());
  // Every step is 1, 2 or 5 times a power of ten, and the count is near the target.
  for (double span : {0.013, 0.7, 3.0, 47.0, 1234.0, 9.9e6})
    for (int target : {2, 5, 9}) {
      const std::vector<double> t = niceTicks(-0.3 * span, 0.7 * span, target);
      ASSERT_GE(t.size(), 2u) << span << " " << target;
      EXPECT_LE(int(t.size()), 2 * target + 1);
      const double step = t[1] - t[0];
      const double mantissa = step / std::pow(10.0, std::floor(std::log10(step) + 1e-9));
      EXPECT_TRUE(std::abs(mantissa - 1) < 1e-6 || std::abs(mantissa - 2) < 1e-6 || std::abs(mantissa - 5) < 1e-6)
          << span << " " << step;
      EXPECT_GE(t.front(), -0.3 * span);
      EXPECT_LE(t.back(), 0.7 * span);
      EXPECT_LT(t.front() - step, -0.3 * span);  // no tick left out at either end
      EXPECT_GT(t.back() + step, 0.7 * span);
    }
}

TEST(Ticks, LogTicksAreDecades) {
  EXPECT_EQ(logTicks(0.5, 2000.0, 6), (std::vector<double>{1.0, 10.0, 100.0, 1000.0}));
  EXPECT_EQ(logTicks(1e-6, 1e-1, 8), (std::vector<double>{1e-6, 1e-5, 1e-4, 1e-3, 1e-2, 1e-1}));
  EXPECT_EQ(logTicks(1e-6, 1e6, 4), (std::vector<double>{1e-6, 1e-3, 1.0, 1e3, 1e6}));
  EXPECT_EQ(logTicks(3.0, 60.0, 6), (std::vector<double>{5.0, 10.0, 20.0, 50.0}));  // under two decades
  EXPECT_EQ(logTicks(2.1, 4.9, 6).size(), niceTicks(2.1, 4.9, 6).size());  // not even 1-2-5
  EXPECT_TRUE(logTicks(0.0, 10.0, 5).empty());
}

TEST(Ticks, LabelsUseTheDigitsTheStepNeeds) {
  EXPECT_EQ(tickLabels({0.0, 0.2, 0.4}, false), (std::vector<std::string>{"0.0", "0.2", "0.4"}));
  EXPECT_EQ(tickLabels({-10.0, 0.0, 10.0}, false), (std::vector<std::string>{"-10", "0", "10"}));
  EXPECT_EQ(tickLabels({0.0035, 0.004}, false), (std::vector<std::string>{"0.0035", "0.0040"}));
  EXPECT_EQ(tickLabels({1.0e5, 1.5e5}, false), (std::vector<std::string>{"1.0e5", "1.5e5"}));
  EXPECT_EQ(tickLabels({0.0, 2e-4, 4e-4}, false), (std::vector<std::string>{"0", "2e-4", "4e-4"}));
  EXPECT_EQ(tickLabels({0.01, 0.1, 1.0, 10.0}, true), (std::vector<std::string>{"0.01", "0.1", "1", "10"}));
  EXPECT_EQ(tickLabels({1e-6, 1e-3, 1.0}, true), (std::vector<std::string>{"1e-6", "1e-3", "1e0"}));
}

TEST(Text, DarkPixelsInsideItsBoxOnly) {
  const std::string text = "Err 1e-3 (gjy)";
  const int scale = 2, x0 = 7, y0 = 5;
  const Eigen::Vector2i size = textSize(text, scale);
  EXPECT_EQ(size, Eigen::Vector2i((6 * int(text.size()) - 1) * scale, 9 * scale));
  Image image(size.x() + 20, size.y() + 12, Eigen::Vector4f::Ones());
  drawText(image, text, x0, y0, scale, Eigen::Vector3f::Zero());
  int inside = 0;
  bool belowBaseline = false;
  for (int y = 0; y < image.height(); ++y)
    for (int x = 0; x < image.width(); ++x) {
      const bool in = x >= x0 && x < x0 + size.x() && y >= y0 && y < y0 + size.y();
      if (!in) {
        ASSERT_FALSE(isDark(image, x, y)) << x << "," << y;
      }
      inside += isDark(image, x, y);
      belowBaseline = belowBaseline || (isDark(image, x, y) && y >= y0 + 7 * scale);  // descenders
    }
  EXPECT_GT(inside, 100);
  EXPECT_LT(inside, size.x() * size.y() / 2);
  EXPECT_TRUE(belowBaseline);
  // Distinct glyphs: '1' and 'l', 'O' and '0' differ; a space draws nothing.
  const auto bitmap = [](const std::string& s) {
    Image glyph(5, 9, Eigen::Vector4f::Ones());
    drawText(glyph, s, 0, 0, 1, Eigen::Vector3f::Zero());
    std::vector<bool> bits;
    for (int y = 0; y < 9; ++y)
      for (int x = 0; x < 5; ++x) bits.push_back(glyph.at(x, y)[0] < 0.5f);
    return bits;
  };
  EXPECT_NE(bitmap("1"), bitmap("l"));
  EXPECT_NE(bitmap("O"), bitmap("0"));
  EXPECT_EQ(bitmap(" "), std::vector<bool>(45, false));
  EXPECT_EQ(bitmap("\x7f"), bitmap("?"));
}

TEST(Plot, PngRoundTrips) {
  TempDir dir;
  Plot plot = diagonalPlot();
  plot.title = "round trip";
  plot.series[0].label = "y = x";
  plot.series[0].markers = true;
  plot.series[0].pointLabels = {"a", "b", "c"};
  const Image image = renderPlot(plot);
  kurage::pipeline::writePlotPng(plot, dir.path() / "plot.png");
  const Image read = readPng(dir.path() / "plot.png");
  CompareOptions exact;
  exact.pixelThreshold = 0.6f / 255.0f;
  exact.allowedFailingFraction = 0.0f;
  const CompareResult result = compareImages(read, image, exact);
  EXPECT_TRUE(result.sizesMatch);
  EXPECT_TRUE(result.passed) << result.maxError;
}

TEST(Plot, BadDataAndEmptyPlotsStillGiveAFramedImage) {
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  Plot plot;
  plot.x.log = plot.y.log = true;
  PlotSeries bad;
  bad.x = {1.0, nan, 10.0, inf, -5.0, 0.0, 100.0, 1e308};
  bad.y = {1.0, 2.0, nan, 3.0, 4.0, 5.0, 100.0, 1e-308};
  bad.markers = true;
  bad.colour = kRed;
  bad.pointLabels = {"p", "q", "r", "s", "t", "u", "v", "w", "extra"};
  plot.series.push_back(bad);
  plot.series.push_back(PlotSeries{});  // empty
  const PlotFrame f = plotFrame(plot);
  EXPECT_TRUE(std::isfinite(f.x.lo) && std::isfinite(f.x.hi) && std::isfinite(f.y.lo) && std::isfinite(f.y.hi));
  const Image image = renderPlot(plot);
  for (const Eigen::Vector2d& p : {f.toPixel(1.0, 1.0), f.toPixel(100.0, 100.0)})
    EXPECT_TRUE(near(srgbAt(image, int(std::lround(p.x())), int(std::lround(p.y()))), kRed, 0.02f));

  for (bool log : {false, true}) {
    Plot empty;
    empty.x.log = empty.y.log = log;
    const PlotFrame e = plotFrame(empty);
    EXPECT_EQ(e.x.lo, log ? 1.0 : 0.0);
    EXPECT_EQ(e.x.hi, log ? 10.0 : 1.0);
    const Image frame = renderPlot(empty);
    for (int y = e.top; y <= e.bottom; ++y) ASSERT_TRUE(isDark(frame, e.left, y) && isDark(frame, e.right, y));
    int labels = 0;  // tick labels under the frame
    for (int y = e.bottom + 6; y < frame.height(); ++y)
      for (int x = 0; x < frame.width(); ++x) labels += isDark(frame, x, y);
    EXPECT_GT(labels, 50);
  }
  Plot tiny;
  tiny.width = 40;
  EXPECT_THROW(renderPlot(tiny), std::invalid_argument);
}

}  // namespace
}  // namespace kurage::render
