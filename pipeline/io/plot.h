// Figures of runs and studies (OUT/bodies.png, OUT/study.png): 2-D line and scatter charts
// described as data here and drawn by gnuplot (Debian's gnuplot-nox, installed by
// .ci/install-deps), as PNG for the web, and SVG and PDF (vector, fonts as text) for papers.
//
// What a figure has: a title (wrapped onto several lines where it is wider than the figure), axis
// labels, linear or log axes (log: values <= 0 skipped), an optional second y axis on the right
// (series with axis = 1), series as lines and/or point markers, a text label beside any point,
// a legend. Values that are not finite are skipped and break their series' line. Colours are
// sRGB; NaN picks gnuplot's default sequence.
//
// Every figure FILE.png comes with FILE.svg, FILE.pdf and FILE.gp, the gnuplot script with the
// data inline, so `gnuplot FILE.gp` redraws all three and a user can restyle a figure by editing
// it. Where gnuplot is missing, the script is still written and a warning names it.
#pragma once

#include <Eigen/Core>

#include <filesystem>
#include <limits>
#include <string>
#include <vector>

namespace kurage::pipeline {

struct PlotSeries {
  std::string label;  // legend text; a series without one has no legend entry
  std::vector<double> x, y;  // same length (extra values in the longer one are ignored)
  Eigen::Vector3f colour = Eigen::Vector3f::Constant(std::numeric_limits<float>::quiet_NaN());  // sRGB
  bool lines = true;
  bool markers = false;
  double lineWidth = 2.0;   // in gnuplot's line width units (1 = a thin line)
  double markerSize = 1.0;  // gnuplot's point size
  std::vector<std::string> pointLabels;  // optional text beside point i (empty string: none)
  int axis = 0;  // 0: left y axis, 1: right y axis
};

struct PlotAxis {
  std::string label;
  bool log = false;
  // Fixed limits; NaN = from the data (gnuplot's autoscale).
  double min = std::numeric_limits<double>::quiet_NaN();
  double max = std::numeric_limits<double>::quiet_NaN();
};

struct Plot {
  std::string title;
  PlotAxis x, y, y2;  // y2 is used only when some series has axis = 1
  std::vector<PlotSeries> series;
  int width = 900, height = 560;  // PNG pixels; SVG and PDF keep the aspect (PDF at 100 px/inch)
  double scale = 1.0;  // text, lines and markers this many times their size (a wide print-size plot); > 0
  bool grid = true;
  bool legend = true;
};

// The title broken at spaces into lines of at most `maxCharacters` (a longer word stays whole).
std::vector<std::string> wrapTitle(const std::string& title, size_t maxCharacters);

// The files a figure is drawn into.
struct PlotOutputs {
  std::filesystem::path png, svg, pdf;
};

// The gnuplot script that draws `plot` into the three outputs (pngcairo, svg, pdfcairo): data
// inline as named blocks, every text noenhanced (no markup read into labels).
std::string gnuplotScript(const Plot& plot, const PlotOutputs& outputs);

// Writes `png` (FILE.png) and, beside it, FILE.svg, FILE.pdf and FILE.gp, each atomically.
// Throws std::runtime_error naming the file when gnuplot fails; prints a warning and writes only
// FILE.gp when gnuplot is not installed.
void writePlot(const Plot& plot, const std::filesystem::path& png);

}  // namespace kurage::pipeline
