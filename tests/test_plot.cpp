// Figures (pipeline/io/plot.h): the gnuplot script says what the plot describes (axes, log
// scales, second axis, skipped values, labels taken literally), and gnuplot turns it into a PNG,
// an SVG and a PDF whose title fits.
#include "pipeline/io/files.h"
#include "pipeline/io/plot.h"
#include "render/image.h"

#include "test_util.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <sstream>

namespace kurage::pipeline {
namespace {

namespace fs = std::filesystem;

Plot sample() {
  Plot plot;
  plot.title = "error against time";
  plot.x.label = "seconds";
  plot.x.log = true;
  plot.y.label = "relative error";
  plot.y.log = true;
  plot.y2.label = "force (N)";
  PlotSeries a;
  a.label = "cfl";
  a.markers = true;
  a.x = {1.0, 2.0, -1.0, 4.0, std::numeric_limits<double>::quiet_NaN()};
  a.y = {0.1, 0.05, 0.03, 0.0, 0.01};
  a.pointLabels = {"0.2", "_x^2 \"quoted\"", "", "", ""};
  PlotSeries b;
  b.label = "force";
  b.axis = 1;
  b.colour = Eigen::Vector3f(1.0f, 0.5f, 0.0f);
  b.x = {1.0, 4.0};
  b.y = {-3.0, 3.0};
  plot.series = {a, b};
  return plot;
}

TEST(Plot, ScriptHoldsTheAxesSeriesAndOnlyDrawableValues) {
  const std::string gp = gnuplotScript(sample(), {"a.png", "a.svg", "a.pdf"});
  EXPECT_NE(gp.find("set logscale x\n"), std::string::npos);
  EXPECT_NE(gp.find("set logscale y\n"), std::string::npos);
  EXPECT_EQ(gp.find("set logscale y2"), std::string::npos);  // the right axis is linear
  EXPECT_NE(gp.find("set y2label \"force (N)\" noenhanced"), std::string::npos);
  EXPECT_NE(gp.find("set y2tics"), std::string::npos);
  // Series 0: x = -1 (log x), y = 0 (log y) and NaN are skipped as blank lines; the rest kept.
  const size_t block = gp.find("$series0 << EOD\n");
  ASSERT_NE(block, std::string::npos);
  const std::string data = gp.substr(block, gp.find("EOD\n", block + 16) - block);
  EXPECT_NE(data.find("1 0.1 \"0.2\"\n2 0.05 \"_x^2 'quoted'\"\n\n\n\n"), std::string::npos) << data;
  // The right-axis series keeps its negative value (a linear axis), in its own colour.
  EXPECT_NE(gp.find("1 -3 \"\"\n4 3 \"\"\n"), std::string::npos);
  EXPECT_NE(gp.find("lc rgb \"#ff8000\""), std::string::npos);
  EXPECT_NE(gp.find("axes x1y2"), std::string::npos);
  // Point labels drawn literally: no enhanced-text markup, the double quotes made single.
  EXPECT_NE(gp.find("with labels"), std::string::npos);
  EXPECT_NE(gp.find("'quoted'"), std::string::npos);
  std::istringstream lines(gp);
  for (std::string line; std::getline(lines, line);)
    if (line.rfind("set title", 0) == 0 || line.find("label \"") != std::string::npos) {
      EXPECT_NE(line.find("noenhanced"), std::string::npos) << line;
    }
}

TEST(Plot, LongTitlesWrapAtSpaces) {
  EXPECT_EQ(wrapTitle("dam_break_fixed_step: relative error of the surge front and the column height", 30),
            (std::vector<std::string>{"dam_break_fixed_step: relative", "error of the surge front and", "the column height"}));
  EXPECT_EQ(wrapTitle("short", 30), std::vector<std::string>{"short"});
  EXPECT_EQ(wrapTitle("averyveryverylongwordthatcannotbreak x", 10),
            (std::vector<std::string>{"averyveryverylongwordthatcannotbreak", "x"}));
}

TEST(Plot, GnuplotDrawsPngSvgAndPdfAndTheScriptRedrawsThem) {
  test::TempDir dir;
  Plot plot = sample();
  plot.title = "a title far too long to fit on one line of a figure only 300 pixels wide, wrapped onto several";
  plot.width = 300;
  plot.height = 220;
  writePlot(plot, dir.path() / "figure.png");
  const render::Image png = render::readPng(dir.path() / "figure.png");
  EXPECT_EQ(png.width(), 300);
  EXPECT_EQ(png.height(), 220);
  // Something is drawn: dark text and lines on the white background.
  int dark = 0;
  for (int y = 0; y < png.height(); ++y)
    for (int x = 0; x < png.width(); ++x) dark += png.at(x, y).head<3>().mean() < 0.3f;
  EXPECT_GT(dark, 200);
  // The title's lines all lie inside the picture: no dark pixel in the outermost columns.
  for (int y = 0; y < png.height(); ++y) {
    EXPECT_GT(png.at(0, y).head<3>().mean(), 0.5f) << y;
    EXPECT_GT(png.at(png.width() - 1, y).head<3>().mean(), 0.5f) << y;
  }
  const std::string svg = readText(dir.path() / "figure.svg");
  EXPECT_NE(svg.find("<svg"), std::string::npos);
  EXPECT_NE(svg.find("wrapped onto several"), std::string::npos);  // text stays text (vector)
  EXPECT_EQ(readText(dir.path() / "figure.pdf").substr(0, 5), "%PDF-");
  const std::string gp = readText(dir.path() / "figure.gp");
  EXPECT_NE(gp.find("set output \"figure.png\""), std::string::npos);
  for (const auto& entry : fs::directory_iterator(dir.path()))  // temporaries are .NAME.PID.N.tmp
    EXPECT_NE(entry.path().extension(), ".tmp") << "left behind: " << entry.path();
}

// Twice the size at scale 2 is the same picture enlarged: its ink grows as the area (x4), where
// unscaled text and lines would keep their size and grow only with the lengths (about x2).
TEST(Plot, AScaledPlotIsTheSamePlotEnlarged) {
  test::TempDir dir;
  const auto ink = [&](int width, int height, double scale) {
    Plot plot = sample();
    plot.width = width;
    plot.height = height;
    plot.scale = scale;
    const fs::path png = dir.path() / ("plot" + std::to_string(width) + ".png");
    writePlot(plot, png);
    const render::Image image = render::readPng(png);
    double sum = 0.0;
    for (int y = 0; y < image.height(); ++y)
      for (int x = 0; x < image.width(); ++x) sum += 1.0 - image.at(x, y).head<3>().mean();
    return sum;
  };
  EXPECT_NE(gnuplotScript([] { Plot p = sample(); p.scale = 2.0; return p; }(), {"a.png", "a.svg", "a.pdf"})
                .find("fontscale 2 linewidth 2 pointscale 2"),
            std::string::npos);
  const double one = ink(450, 280, 1.0), two = ink(900, 560, 2.0);
  EXPECT_GT(two / one, 3.2);
  EXPECT_LT(two / one, 4.8);
}

TEST(Plot, AnEmptyPlotStillGivesItsAxes) {
  test::TempDir dir;
  Plot plot;
  plot.title = "nothing yet";
  writePlot(plot, dir.path() / "empty.png");
  EXPECT_EQ(render::readPng(dir.path() / "empty.png").width(), 900);
}

}  // namespace
}  // namespace kurage::pipeline
