// Plots: 2-D line and scatter charts rendered to an Image (and PNG), with no dependency beyond
// Eigen and render/image.h. For the figures of a run (force and depth against time, with a second
// y axis) and of studies (error against wall time on log axes, each point labelled with its knob).
//
// What it draws: a white background; a frame around the plotting area with outward tick marks
// and numeric tick labels ("nice" 1/2/5 x 10^k steps on linear axes, decades on log axes, with
// minor ticks at 2..9 x 10^k); light grid lines at the major ticks; the title above; the x label
// below; the y label rotated along the left edge; an optional second y axis on the right with
// its own scale and label (used when a series has axis = 1); series as anti-aliased polylines
// and/or filled discs, clipped to the plotting area; a text label beside any point; a legend in
// the corner of the plotting area that covers the fewest points. Text uses a built-in 5x7 bitmap
// font (ASCII 32..126, descenders below; other bytes are drawn as '?') at an integer scale.
//
// Data: values that are not finite, and values <= 0 on a log axis, are skipped; a skipped point
// breaks its series' line. An empty series or plot still gives a framed image with axes.
// Colours are sRGB in [0, 1], as in a colour picker or a PNG; the returned Image holds linear
// values like every Image (writePng encodes them back exactly). Row 0 is the top.
//
// It won't: draw bar charts, error bars, dashed lines, or text outside ASCII; it does not avoid
// collisions between point labels.
#pragma once

#include "render/image.h"

#include <Eigen/Core>

#include <filesystem>
#include <limits>
#include <string>
#include <vector>

namespace kurage::render {

struct PlotSeries {
  std::string label;  // legend text; a series without one has no legend entry
  std::vector<double> x, y;  // same length (extra values in the longer one are ignored)
  // sRGB; NaN (default) picks plotColour(index of the series)
  Eigen::Vector3f colour = Eigen::Vector3f::Constant(std::numeric_limits<float>::quiet_NaN());
  bool lines = true;
  bool markers = false;
  double lineWidth = 2.0;   // pixels (finite, >= 0, as is markerSize)
  double markerSize = 8.0;  // disc diameter, pixels
  std::vector<std::string> pointLabels;  // optional text beside point i (empty string: none)
  int axis = 0;  // 0: left y axis, 1: right y axis
};

struct PlotAxis {
  std::string label;
  bool log = false;
  // Fixed limits; NaN (or any non-finite value) = from the data, with a 5% margin. Log axes
  // need limits > 0.
  double min = std::numeric_limits<double>::quiet_NaN();
  double max = std::numeric_limits<double>::quiet_NaN();
};

struct Plot {
  std::string title;
  PlotAxis x, y, y2;  // y2 is used only when some series has axis = 1
  std::vector<PlotSeries> series;
  int width = 800, height = 500;  // pixels
  int textScale = 2;              // the 5x7 font is drawn at this integer scale
  bool grid = true;
  bool legend = true;
};

// The resolved data range of one axis.
struct AxisRange {
  double lo = 0.0, hi = 1.0;
  bool log = false;
  // 0 at lo, 1 at hi; linear in log10(v) on a log axis; NaN when v cannot be drawn.
  double fraction(double v) const;
};

// Where the plotting area lies in the image and the scales of its axes. The frame lines lie on
// pixel columns left and right and rows top and bottom; pixel (i, j) is centred at (i, j).
struct PlotFrame {
  int left = 0, top = 0, right = 0, bottom = 0;
  AxisRange x, y, y2;
  bool hasY2 = false;
  // Pixel coordinates of a data point (axis 0: left y axis, 1: right); NaN when it cannot be
  // drawn. Points outside the ranges map outside the plotting area.
  Eigen::Vector2d toPixel(double x, double y, int axis = 0) const;
};

// The layout renderPlot uses. Throws std::invalid_argument for a size that leaves no plotting
// area, a text scale < 1, fixed limits with min >= max or a log limit <= 0.
PlotFrame plotFrame(const Plot& plot);

// Renders the plot (exceptions as plotFrame).
Image renderPlot(const Plot& plot);

// Ticks at multiples of a "nice" step (1, 2 or 5 x 10^k) inside [lo, hi]: about `target`
// intervals between lo and hi, and at least two ticks when lo < hi. Values are the nearest
// doubles to the decimal numbers (0.3, not 0.30000000000000004). Empty for non-finite input or
// target < 1.
std::vector<double> niceTicks(double lo, double hi, int target);

// Ticks for a log axis over [lo, hi] (0 < lo < hi): powers of ten, every n-th decade when there
// are more than target + 1 of them; 1, 2, 5 x 10^k when the range holds fewer than two decades;
// niceTicks when even those give fewer than two. Empty for lo <= 0 or non-finite input.
std::vector<double> logTicks(double lo, double hi, int target);

// Labels for ticks: fixed-point with as many decimals as the step needs ("0.0", "0.5", "1.0"),
// or "2e-5"-style for the whole axis when its ticks reach 1e5 or are all below 1e-3 in
// magnitude (log axes: when any tick is outside [1e-3, 1e5)).
std::vector<std::string> tickLabels(const std::vector<double>& ticks, bool log);

// Series colours: a qualitative palette of 10 sRGB colours, repeating.
Eigen::Vector3f plotColour(int index);

// The built-in font: size in pixels of `text` at `scale` (5x7 glyphs on a 6-pixel advance, 9
// rows high with descenders), and drawing it with its top-left corner at (x, y), clipped to the
// image. The colour is sRGB; pixels are set, not blended.
Eigen::Vector2i textSize(const std::string& text, int scale);
void drawText(Image& image, const std::string& text, int x, int y, int scale, const Eigen::Vector3f& colour);

}  // namespace kurage::render
