// Plots rendered to an Image; see plot.h.
//
// Drawing happens on an Image that holds sRGB-encoded values, so anti-aliased edges blend the way
// plotting libraries blend them; renderPlot converts to linear values at the end. The lines and
// markers of one series are first rasterised into a coverage mask (the maximum over its pieces,
// so a joint is not blended twice) and then composited once.
#include "render/plot.h"

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <stdexcept>

namespace kurage::render {

namespace {

constexpr int kGlyphRows = 9;  // rows 0-6 above the baseline, 7-8 descenders
constexpr int kAscent = 7;
constexpr int kAdvance = 6;    // 5 columns and a gap

// 5x7 ASCII font, characters 32..126: one byte per row, bit 4 the leftmost column.
constexpr std::uint8_t kFont[95][kGlyphRows] = {
    {0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00},  // space
    {0x04, 0x04, 0x04, 0x04, 0x04, 0x00, 0x04, 0x00, 0x00},  // !
    {0x0A, 0x0A, 0x0A, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00},  // "
    {0x0A, 0x0A, 0x1F, 0x0A, 0x1F, 0x0A, 0x0A, 0x00, 0x00},  // #
    {0x04, 0x0F, 0x14, 0x0E, 0x05, 0x1E, 0x04, 0x00, 0x00},  // $
    {0x18, 0x19, 0x02, 0x04, 0x08, 0x13, 0x03, 0x00, 0x00},  // %
    {0x0C, 0x12, 0x14, 0x08, 0x15, 0x12, 0x0D, 0x00, 0x00},  // &
    {0x04, 0x04, 0x08, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00},  // quote
    {0x02, 0x04, 0x08, 0x08, 0x08, 0x04, 0x02, 0x00, 0x00},  // (
    {0x08, 0x04, 0x02, 0x02, 0x02, 0x04, 0x08, 0x00, 0x00},  // )
    {0x00, 0x04, 0x15, 0x0E, 0x15, 0x04, 0x00, 0x00, 0x00},  // *
    {0x00, 0x04, 0x04, 0x1F, 0x04, 0x04, 0x00, 0x00, 0x00},  // +
    {0x00, 0x00, 0x00, 0x00, 0x00, 0x0C, 0x0C, 0x04, 0x08},  // ,
    {0x00, 0x00, 0x00, 0x1F, 0x00, 0x00, 0x00, 0x00, 0x00},  // -
    {0x00, 0x00, 0x00, 0x00, 0x00, 0x0C, 0x0C, 0x00, 0x00},  // .
    {0x00, 0x01, 0x02, 0x04, 0x08, 0x10, 0x00, 0x00, 0x00},  // /
    {0x0E, 0x11, 0x13, 0x15, 0x19, 0x11, 0x0E, 0x00, 0x00},  // 0
    {0x04, 0x0C, 0x04, 0x04, 0x04, 0x04, 0x0E, 0x00, 0x00},  // 1
    {0x0E, 0x11, 0x01, 0x02, 0x04, 0x08, 0x1F, 0x00, 0x00},  // 2
    {0x1F, 0x02, 0x04, 0x02, 0x01, 0x11, 0x0E, 0x00, 0x00},  // 3
    {0x02, 0x06, 0x0A, 0x12, 0x1F, 0x02, 0x02, 0x00, 0x00},  // 4
    {0x1F, 0x10, 0x1E, 0x01, 0x01, 0x11, 0x0E, 0x00, 0x00},  // 5
    {0x06, 0x08, 0x10, 0x1E, 0x11, 0x11, 0x0E, 0x00, 0x00},  // 6
    {0x1F, 0x01, 0x02, 0x04, 0x08, 0x08, 0x08, 0x00, 0x00},  // 7
    {0x0E, 0x11, 0x11, 0x0E, 0x11, 0x11, 0x0E, 0x00, 0x00},  // 8
    {0x0E, 0x11, 0x11, 0x0F, 0x01, 0x02, 0x0C, 0x00, 0x00},  // 9
    {0x00, 0x0C, 0x0C, 0x00, 0x0C, 0x0C, 0x00, 0x00, 0x00},  // :
    {0x00, 0x0C, 0x0C, 0x00, 0x0C, 0x0C, 0x04, 0x08, 0x00},  // ;
    {0x02, 0x04, 0x08, 0x10, 0x08, 0x04, 0x02, 0x00, 0x00},  // <
    {0x00, 0x00, 0x1F, 0x00, 0x1F, 0x00, 0x00, 0x00, 0x00},  // =
    {0x08, 0x04, 0x02, 0x01, 0x02, 0x04, 0x08, 0x00, 0x00},  // >
    {0x0E, 0x11, 0x01, 0x02, 0x04, 0x00, 0x04, 0x00, 0x00},  // ?
    {0x0E, 0x11, 0x01, 0x0D, 0x15, 0x15, 0x0E, 0x00, 0x00},  // @
    {0x0E, 0x11, 0x11, 0x1F, 0x11, 0x11, 0x11, 0x00, 0x00},  // A
    {0x1E, 0x11, 0x11, 0x1E, 0x11, 0x11, 0x1E, 0x00, 0x00},  // B
    {0x0E, 0x11, 0x10, 0x10, 0x10, 0x11, 0x0E, 0x00, 0x00},  // C
    {0x1C, 0x12, 0x11, 0x11, 0x11, 0x12, 0x1C, 0x00, 0x00},  // D
    {0x1F, 0x10, 0x10, 0x1E, 0x10, 0x10, 0x1F, 0x00, 0x00},  // E
    {0x1F, 0x10, 0x10, 0x1E, 0x10, 0x10, 0x10, 0x00, 0x00},  // F
    {0x0E, 0x11, 0x10, 0x17, 0x11, 0x11, 0x0F, 0x00, 0x00},  // G
    {0x11, 0x11, 0x11, 0x1F, 0x11, 0x11, 0x11, 0x00, 0x00},  // H
    {0x0E, 0x04, 0x04, 0x04, 0x04, 0x04, 0x0E, 0x00, 0x00},  // I
    {0x07, 0x02, 0x02, 0x02, 0x02, 0x12, 0x0C, 0x00, 0x00},  // J
    {0x11, 0x12, 0x14, 0x18, 0x14, 0x12, 0x11, 0x00, 0x00},  // K
    {0x10, 0x10, 0x10, 0x10, 0x10, 0x10, 0x1F, 0x00, 0x00},  // L
    {0x11, 0x1B, 0x15, 0x15, 0x11, 0x11, 0x11, 0x00, 0x00},  // M
    {0x11, 0x11, 0x19, 0x15, 0x13, 0x11, 0x11, 0x00, 0x00},  // N
    {0x0E, 0x11, 0x11, 0x11, 0x11, 0x11, 0x0E, 0x00, 0x00},  // O
    {0x1E, 0x11, 0x11, 0x1E, 0x10, 0x10, 0x10, 0x00, 0x00},  // P
    {0x0E, 0x11, 0x11, 0x11, 0x15, 0x12, 0x0D, 0x00, 0x00},  // Q
    {0x1E, 0x11, 0x11, 0x1E, 0x14, 0x12, 0x11, 0x00, 0x00},  // R
    {0x0F, 0x10, 0x10, 0x0E, 0x01, 0x01, 0x1E, 0x00, 0x00},  // S
    {0x1F, 0x04, 0x04, 0x04, 0x04, 0x04, 0x04, 0x00, 0x00},  // T
    {0x11, 0x11, 0x11, 0x11, 0x11, 0x11, 0x0E, 0x00, 0x00},  // U
    {0x11, 0x11, 0x11, 0x11, 0x11, 0x0A, 0x04, 0x00, 0x00},  // V
    {0x11, 0x11, 0x11, 0x15, 0x15, 0x15, 0x0A, 0x00, 0x00},  // W
    {0x11, 0x11, 0x0A, 0x04, 0x0A, 0x11, 0x11, 0x00, 0x00},  // X
    {0x11, 0x11, 0x0A, 0x04, 0x04, 0x04, 0x04, 0x00, 0x00},  // Y
    {0x1F, 0x01, 0x02, 0x04, 0x08, 0x10, 0x1F, 0x00, 0x00},  // Z
    {0x0E, 0x08, 0x08, 0x08, 0x08, 0x08, 0x0E, 0x00, 0x00},  // [
    {0x00, 0x10, 0x08, 0x04, 0x02, 0x01, 0x00, 0x00, 0x00},  // backslash
    {0x0E, 0x02, 0x02, 0x02, 0x02, 0x02, 0x0E, 0x00, 0x00},  // ]
    {0x04, 0x0A, 0x11, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00},  // ^
    {0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x1F, 0x00},  // _
    {0x08, 0x04, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00},  // `
    {0x00, 0x00, 0x0E, 0x01, 0x0F, 0x11, 0x0F, 0x00, 0x00},  // a
    {0x10, 0x10, 0x16, 0x19, 0x11, 0x11, 0x1E, 0x00, 0x00},  // b
    {0x00, 0x00, 0x0E, 0x10, 0x10, 0x11, 0x0E, 0x00, 0x00},  // c
    {0x01, 0x01, 0x0D, 0x13, 0x11, 0x11, 0x0F, 0x00, 0x00},  // d
    {0x00, 0x00, 0x0E, 0x11, 0x1F, 0x10, 0x0E, 0x00, 0x00},  // e
    {0x06, 0x09, 0x08, 0x1C, 0x08, 0x08, 0x08, 0x00, 0x00},  // f
    {0x00, 0x00, 0x0F, 0x11, 0x11, 0x11, 0x0F, 0x01, 0x0E},  // g
    {0x10, 0x10, 0x16, 0x19, 0x11, 0x11, 0x11, 0x00, 0x00},  // h
    {0x04, 0x00, 0x0C, 0x04, 0x04, 0x04, 0x0E, 0x00, 0x00},  // i
    {0x02, 0x00, 0x06, 0x02, 0x02, 0x02, 0x02, 0x12, 0x0C},  // j
    {0x10, 0x10, 0x12, 0x14, 0x18, 0x14, 0x12, 0x00, 0x00},  // k
    {0x0C, 0x04, 0x04, 0x04, 0x04, 0x04, 0x0E, 0x00, 0x00},  // l
    {0x00, 0x00, 0x1A, 0x15, 0x15, 0x11, 0x11, 0x00, 0x00},  // m
    {0x00, 0x00, 0x16, 0x19, 0x11, 0x11, 0x11, 0x00, 0x00},  // n
    {0x00, 0x00, 0x0E, 0x11, 0x11, 0x11, 0x0E, 0x00, 0x00},  // o
    {0x00, 0x00, 0x1E, 0x11, 0x11, 0x11, 0x1E, 0x10, 0x10},  // p
    {0x00, 0x00, 0x0F, 0x11, 0x11, 0x11, 0x0F, 0x01, 0x01},  // q
    {0x00, 0x00, 0x16, 0x19, 0x10, 0x10, 0x10, 0x00, 0x00},  // r
    {0x00, 0x00, 0x0E, 0x10, 0x0E, 0x01, 0x1E, 0x00, 0x00},  // s
    {0x08, 0x08, 0x1C, 0x08, 0x08, 0x09, 0x06, 0x00, 0x00},  // t
    {0x00, 0x00, 0x11, 0x11, 0x11, 0x13, 0x0D, 0x00, 0x00},  // u
    {0x00, 0x00, 0x11, 0x11, 0x11, 0x0A, 0x04, 0x00, 0x00},  // v
    {0x00, 0x00, 0x11, 0x11, 0x15, 0x15, 0x0A, 0x00, 0x00},  // w
    {0x00, 0x00, 0x11, 0x0A, 0x04, 0x0A, 0x11, 0x00, 0x00},  // x
    {0x00, 0x00, 0x11, 0x11, 0x11, 0x11, 0x0F, 0x01, 0x0E},  // y
    {0x00, 0x00, 0x1F, 0x02, 0x04, 0x08, 0x1F, 0x00, 0x00},  // z
    {0x02, 0x04, 0x04, 0x08, 0x04, 0x04, 0x02, 0x00, 0x00},  // {
    {0x04, 0x04, 0x04, 0x04, 0x04, 0x04, 0x04, 0x04, 0x04},  // |
    {0x08, 0x04, 0x04, 0x02, 0x04, 0x04, 0x08, 0x00, 0x00},  // }
    {0x00, 0x00, 0x08, 0x15, 0x02, 0x00, 0x00, 0x00, 0x00},  // ~
};

using Colour = Eigen::Vector3f;  // sRGB
const Colour kInk(0.1f, 0.1f, 0.1f);
const Colour kFrameColour(0.2f, 0.2f, 0.2f);
const Colour kGridColour(0.9f, 0.9f, 0.9f);
const Colour kLegendBorder(0.7f, 0.7f, 0.7f);
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// 10^k, the nearest double to the decimal number (1/1000 is, 10^-3 from pow may not be).
double pow10(int k) { return k >= 0 ? std::pow(10.0, k) : 1.0 / std::pow(10.0, -k); }

bool usable(double v, bool log) { return std::isfinite(v) && (!log || v > 0); }
double toAxis(double v, bool log) { return log ? std::log10(v) : v; }
double fromAxis(double t, bool log) { return log ? std::pow(10.0, t) : t; }

Eigen::Vector4f opaque(const Colour& c) { return {c.x(), c.y(), c.z(), 1.0f}; }

// Sets the pixels of `text`, its box's top-left corner at (x, y). Vertical text is turned a
// quarter turn anticlockwise (it reads upwards); (x, y) is then the top-left of the turned box.
void putText(Image& image, const std::string& text, int x, int y, int scale, const Eigen::Vector4f& value,
             bool vertical = false) {
  const int length = textSize(text, scale).x();
  for (size_t i = 0; i < text.size(); ++i) {
    const unsigned char c = static_cast<unsigned char>(text[i]);
    const std::uint8_t* glyph = kFont[(c >= 32 && c <= 126 ? c : '?') - 32];
    for (int row = 0; row < kGlyphRows; ++row)
      for (int col = 0; col < 5; ++col) {
        if (!((glyph[row] >> (4 - col)) & 1)) continue;
        for (int dv = 0; dv < scale; ++dv)
          for (int du = 0; du < scale; ++du) {
            const int u = (static_cast<int>(i) * kAdvance + col) * scale + du, v = row * scale + dv;
            const int px = vertical ? x + v : x + u, py = vertical ? y + length - 1 - u : y + v;
            if (px >= 0 && py >= 0 && px < image.width() && py < image.height()) image.at(px, py) = value;
          }
      }
  }
}

void putText(Image& image, const std::string& text, int x, int y, int scale, const Colour& colour,
             bool vertical = false) {
  putText(image, text, x, y, scale, opaque(colour), vertical);
}

// Anti-aliased coverage in [0, 1] of one series (or legend sample), the maximum over its pieces,
// limited to a clip rectangle (inclusive pixel bounds).
class Mask {
public:
  Mask(int width, int height, int x0, int y0, int x1, int y1)
      : width_(width), x0_(std::max(x0, 0)), y0_(std::max(y0, 0)), x1_(std::min(x1, width - 1)),
        y1_(std::min(y1, height - 1)), coverage_(static_cast<size_t>(width) * height, 0.0f) {}

  // A segment `width` pixels wide with round ends.
  void segment(Eigen::Vector2d p, Eigen::Vector2d q, double width) {
    const double r = 0.5 * width;
    if (!clip(p, q, r + 1.0)) return;
    const Eigen::Vector2d d = q - p;
    const double length2 = d.squaredNorm();
    cover(p.cwiseMin(q), p.cwiseMax(q), r, [&](const Eigen::Vector2d& c) {
      const double t = length2 > 0.0 ? std::clamp((c - p).dot(d) / length2, 0.0, 1.0) : 0.0;
      return (p + t * d - c).norm();
    });
  }

  void disc(const Eigen::Vector2d& centre, double diameter) {
    cover(centre, centre, 0.5 * diameter, [&](const Eigen::Vector2d& c) { return (c - centre).norm(); });
  }

  // Blends `colour` over the image with the coverage as opacity.
  void paint(Image& image, const Colour& colour) const {
    for (int y = y0_; y <= y1_; ++y)
      for (int x = x0_; x <= x1_; ++x) {
        const float a = coverage_[static_cast<size_t>(y) * width_ + x];
        if (a > 0.0f) image.at(x, y).head<3>() = (1.0f - a) * image.at(x, y).head<3>() + a * colour;
      }
  }

private:
  // Coverage of the pixels within r + 1 of the box [lo, hi]: a shape of radius r around the set
  // that `distance` measures, with a one-pixel linear ramp at its edge.
  template <class Distance>
  void cover(const Eigen::Vector2d& lo, const Eigen::Vector2d& hi, double r, Distance distance) {
    const int xa = static_cast<int>(std::max(std::floor(lo.x() - r - 1.0), double(x0_)));
    const int xb = static_cast<int>(std::min(std::ceil(hi.x() + r + 1.0), double(x1_)));
    const int ya = static_cast<int>(std::max(std::floor(lo.y() - r - 1.0), double(y0_)));
    const int yb = static_cast<int>(std::min(std::ceil(hi.y() + r + 1.0), double(y1_)));
    for (int y = ya; y <= yb; ++y)
      for (int x = xa; x <= xb; ++x) {
        const double a = std::clamp(r + 0.5 - distance(Eigen::Vector2d(x, y)), 0.0, 1.0);
        float& c = coverage_[static_cast<size_t>(y) * width_ + x];
        c = std::max(c, static_cast<float>(a));
      }
  }

  // Liang-Barsky: cuts p-q to the clip rectangle grown by `margin`; false when nothing is left.
  bool clip(Eigen::Vector2d& p, Eigen::Vector2d& q, double margin) const {
    const Eigen::Vector2d lo(x0_ - margin, y0_ - margin), hi(x1_ + margin, y1_ + margin), d = q - p;
    double t0 = 0.0, t1 = 1.0;
    for (int a = 0; a < 2; ++a) {
      if (d[a] == 0.0) {
        if (p[a] < lo[a] || p[a] > hi[a]) return false;
        continue;
      }
      double ta = (lo[a] - p[a]) / d[a], tb = (hi[a] - p[a]) / d[a];
      if (ta > tb) std::swap(ta, tb);
      t0 = std::max(t0, ta);
      t1 = std::min(t1, tb);
      if (t0 > t1) return false;
    }
    const Eigen::Vector2d start = p;
    p = start + t0 * d;
    q = start + t1 * d;
    return true;
  }

  int width_, x0_, y0_, x1_, y1_;
  std::vector<float> coverage_;
};

// An axis's range from its fixed limits and the data values that can be drawn on it.
AxisRange resolveRange(const PlotAxis& axis, const std::vector<double>& values) {
  const bool fixedMin = std::isfinite(axis.min), fixedMax = std::isfinite(axis.max);
  if (axis.log && ((fixedMin && axis.min <= 0) || (fixedMax && axis.max <= 0)))
    throw std::invalid_argument("plot: log axis '" + axis.label + "' needs limits > 0");
  if (fixedMin && fixedMax && !(axis.min < axis.max))
    throw std::invalid_argument("plot: axis '" + axis.label + "' has min >= max");
  // In axis units (log10 on a log axis), bounded so that spans, margins and 10^t stay finite.
  const double bound = axis.log ? 300.0 : 1e300;
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (double v : values) {
    const double t = std::clamp(toAxis(v, axis.log), -bound, bound);
    lo = std::min(lo, t);
    hi = std::max(hi, t);
  }
  if (lo > hi) {  // no data: [0, 1], or [1, 10] on a log axis
    lo = 0.0;
    hi = 1.0;
  } else if (lo == hi) {
    const double d = axis.log ? 0.5 : (lo == 0.0 ? 1.0 : 0.1 * std::fabs(lo));
    lo -= d;
    hi += d;
  } else {
    const double margin = 0.05 * hi - 0.05 * lo;
    lo = std::max(lo - margin, -bound);
    hi = std::min(hi + margin, bound);
  }
  if (fixedMin) lo = toAxis(axis.min, axis.log);
  if (fixedMax) hi = toAxis(axis.max, axis.log);
  if (!(lo < hi)) {  // one fixed limit beyond all the data
    if (fixedMax) lo = hi - 1.0;
    else hi = lo + 1.0;
  }
  return {fromAxis(lo, axis.log), fromAxis(hi, axis.log), axis.log};
}

std::vector<double> axisTicks(const AxisRange& range, int pixels, int spacing) {
  const int target = std::max(2, pixels / spacing);
  return range.log ? logTicks(range.lo, range.hi, target) : niceTicks(range.lo, range.hi, target);
}

int widest(const std::vector<std::string>& labels, int scale) {
  int w = 0;
  for (const std::string& label : labels) w = std::max(w, textSize(label, scale).x());
  return w;
}

struct Layout {
  PlotFrame frame;
  std::vector<double> xTicks, yTicks, y2Ticks;
  int scale, pad, tickLength, lineHeight;
};

Layout layout(const Plot& plot) {
  if (plot.textScale < 1) throw std::invalid_argument("plot: text scale must be >= 1");
  Layout L;
  PlotFrame& f = L.frame;
  const int s = L.scale = plot.textScale;
  L.pad = 3 * s;
  L.tickLength = 5;
  L.lineHeight = kGlyphRows * s;

  // Ranges from the points that can be drawn (both coordinates usable).
  std::vector<double> xs, ys[2];
  for (const PlotSeries& series : plot.series) {
    const int axis = series.axis == 1 ? 1 : 0;
    f.hasY2 = f.hasY2 || axis == 1;
    const bool yLog = (axis == 1 ? plot.y2 : plot.y).log;
    for (size_t i = 0; i < std::min(series.x.size(), series.y.size()); ++i)
      if (usable(series.x[i], plot.x.log) && usable(series.y[i], yLog)) {
        xs.push_back(series.x[i]);
        ys[axis].push_back(series.y[i]);
      }
  }
  f.x = resolveRange(plot.x, xs);
  f.y = resolveRange(plot.y, ys[0]);
  if (f.hasY2) f.y2 = resolveRange(plot.y2, ys[1]);

  f.top = L.pad + (plot.title.empty() ? L.lineHeight / 2 : L.lineHeight + L.pad);
  f.bottom = plot.height - 1 - (L.tickLength + 2 * L.pad + L.lineHeight) -
             (plot.x.label.empty() ? 0 : L.pad + L.lineHeight);
  const auto side = [&](const std::vector<double>& ticks, const AxisRange& range, const std::string& label) {
    return L.tickLength + 2 * L.pad + widest(tickLabels(ticks, range.log), s) +
           (label.empty() ? 0 : L.pad + L.lineHeight);
  };
  L.yTicks = axisTicks(f.y, f.bottom - f.top, 30 * s);
  f.left = side(L.yTicks, f.y, plot.y.label);
  if (f.hasY2) {
    L.y2Ticks = axisTicks(f.y2, f.bottom - f.top, 30 * s);
    f.right = plot.width - 1 - side(L.y2Ticks, f.y2, plot.y2.label);
  } else {
    f.right = plot.width - 1 - (L.pad + 3 * kAdvance * s);  // about half a tick label
  }
  if (f.right - f.left < 16 || f.bottom - f.top < 16)
    throw std::invalid_argument("plot: " + std::to_string(plot.width) + "x" + std::to_string(plot.height) +
                                " pixels leave no room for the plotting area");
  L.xTicks = axisTicks(f.x, f.right - f.left, 50 * s);
  return L;
}

// Minor ticks of a log axis: m x 10^k for m = 2..9, when the range spans at most 8 decades.
std::vector<double> minorLogTicks(const AxisRange& range) {
  std::vector<double> ticks;
  if (!range.log || range.hi / range.lo > 1e8) return ticks;
  for (int k = static_cast<int>(std::floor(std::log10(range.lo))); pow10(k) <= range.hi; ++k)
    for (int m = 2; m <= 9; ++m)
      if (const double v = m * pow10(k); v >= range.lo && v <= range.hi) ticks.push_back(v);
  return ticks;
}

void drawAxes(Image& image, const Plot& plot, const Layout& L) {
  const PlotFrame& f = L.frame;
  const int s = L.scale, w = image.width();
  for (int x = f.left; x <= f.right; ++x) image.at(x, f.top) = image.at(x, f.bottom) = opaque(kFrameColour);
  for (int y = f.top; y <= f.bottom; ++y) image.at(f.left, y) = image.at(f.right, y) = opaque(kFrameColour);

  // x: marks below the frame, labels centred under them.
  const std::vector<std::string> xLabels = tickLabels(L.xTicks, f.x.log);
  const auto xMark = [&](double v, int length) {
    const double px = std::round(f.toPixel(v, f.y.lo).x());
    if (!(px >= f.left && px <= f.right)) return -1;
    for (int y = f.bottom + 1; y <= f.bottom + length; ++y) image.at(static_cast<int>(px), y) = opaque(kFrameColour);
    return static_cast<int>(px);
  };
  for (double v : minorLogTicks(f.x)) xMark(v, L.tickLength - 2);
  for (size_t i = 0; i < L.xTicks.size(); ++i)
    if (const int px = xMark(L.xTicks[i], L.tickLength); px >= 0) {
      const int tw = textSize(xLabels[i], s).x();
      putText(image, xLabels[i], std::max(0, std::min(px - tw / 2, w - tw)), f.bottom + L.tickLength + L.pad, s, kInk);
    }

  // y (left) and y2 (right): marks outside the frame, labels beside them, centred on the digits.
  const auto yAxis = [&](const AxisRange& range, const std::vector<double>& ticks, int axis) {
    const std::vector<std::string> labels = tickLabels(ticks, range.log);
    const int sign = axis == 0 ? -1 : 1, edge = axis == 0 ? f.left : f.right;
    const auto mark = [&](double v, int length) {
      const double py = std::round(f.toPixel(f.x.lo, v, axis).y());
      if (!(py >= f.top && py <= f.bottom)) return -1;
      for (int d = 1; d <= length; ++d) image.at(edge + sign * d, static_cast<int>(py)) = opaque(kFrameColour);
      return static_cast<int>(py);
    };
    for (double v : minorLogTicks(range)) mark(v, L.tickLength - 2);
    for (size_t i = 0; i < ticks.size(); ++i)
      if (const int py = mark(ticks[i], L.tickLength); py >= 0) {
        const int tw = textSize(labels[i], s).x(), gap = L.tickLength + L.pad;
        putText(image, labels[i], axis == 0 ? edge - gap - tw : edge + gap, py - kAscent * s / 2, s, kInk);
      }
  };
  yAxis(f.y, L.yTicks, 0);
  if (f.hasY2) yAxis(f.y2, L.y2Ticks, 1);

  // Axis labels and the title.
  const int midX = (f.left + f.right) / 2, midY = (f.top + f.bottom) / 2;
  if (!plot.x.label.empty())
    putText(image, plot.x.label, midX - textSize(plot.x.label, s).x() / 2,
            f.bottom + L.tickLength + 2 * L.pad + L.lineHeight, s, kInk);
  if (!plot.y.label.empty())
    putText(image, plot.y.label, L.pad, std::max(0, midY - textSize(plot.y.label, s).x() / 2), s, kInk, true);
  if (f.hasY2 && !plot.y2.label.empty())
    putText(image, plot.y2.label, w - L.pad - L.lineHeight, std::max(0, midY - textSize(plot.y2.label, s).x() / 2),
            s, kInk, true);
  if (!plot.title.empty()) {
    const int x = std::max(0, midX - textSize(plot.title, s).x() / 2);
    putText(image, plot.title, x, L.pad, s, kInk);
    putText(image, plot.title, x + 1, L.pad, s, kInk);  // bold
  }
}

// Pixel positions of a series' points; NaN where a point cannot be drawn.
std::vector<Eigen::Vector2d> seriesPixels(const PlotFrame& f, const PlotSeries& series) {
  std::vector<Eigen::Vector2d> pixels(std::min(series.x.size(), series.y.size()));
  for (size_t i = 0; i < pixels.size(); ++i) {
    pixels[i] = f.toPixel(series.x[i], series.y[i], series.axis == 1 ? 1 : 0);
    if (!pixels[i].allFinite()) pixels[i].setConstant(kNaN);
  }
  return pixels;
}

bool inside(const PlotFrame& f, const Eigen::Vector2d& p) {
  return p.x() >= f.left && p.x() <= f.right && p.y() >= f.top && p.y() <= f.bottom;
}

Colour seriesColour(const Plot& plot, size_t index) {
  const Colour& c = plot.series[index].colour;
  return c.allFinite() ? c : plotColour(static_cast<int>(index));
}

void drawSeries(Image& image, const PlotFrame& f, const PlotSeries& series, const Colour& colour) {
  const std::vector<Eigen::Vector2d> pixels = seriesPixels(f, series);
  Mask mask(image.width(), image.height(), f.left, f.top, f.right, f.bottom);
  for (size_t i = 0; i < pixels.size(); ++i) {
    if (!pixels[i].allFinite()) continue;
    if (series.lines && i > 0 && pixels[i - 1].allFinite()) mask.segment(pixels[i - 1], pixels[i], series.lineWidth);
    if (series.markers) mask.disc(pixels[i], series.markerSize);
  }
  mask.paint(image, colour);
}

// Text beside each labelled point: of the four places diagonal to it that fit inside the frame,
// the one covering the fewest pixels drawn so far (lines, markers, earlier labels; ties: the first
// of above right, below right, above left, below left).
void drawPointLabels(Image& image, const PlotFrame& f, const PlotSeries& series, const Colour& colour, int s) {
  const std::vector<Eigen::Vector2d> pixels = seriesPixels(f, series);
  const int offset = static_cast<int>(std::ceil(0.5 * std::max(series.markerSize, series.lineWidth))) + 2;
  for (size_t i = 0; i < std::min(pixels.size(), series.pointLabels.size()); ++i) {
    const std::string& text = series.pointLabels[i];
    if (text.empty() || !inside(f, pixels[i])) continue;
    const int px = static_cast<int>(std::lround(pixels[i].x())), py = static_cast<int>(std::lround(pixels[i].y()));
    const Eigen::Vector2i size = textSize(text, s);
    Eigen::Vector2i best(px + offset, py - offset - kAscent * s);
    int fewest = INT_MAX;
    for (int side : {1, -1})
      for (int below : {0, 1}) {
        const int x = side > 0 ? px + offset : px - offset - size.x();
        const int y = below ? py + offset : py - offset - kAscent * s;
        if (x <= f.left || x + size.x() >= f.right || y <= f.top || y + size.y() >= f.bottom) continue;
        int ink = 0;
        for (int v = y; v < y + size.y(); ++v)
          for (int u = x; u < x + size.x(); ++u) ink += image.at(u, v).head<3>().minCoeff() < 0.85f;
        if (ink < fewest) {
          fewest = ink;
          best = {x, y};
        }
      }
    putText(image, text, best.x(), best.y(), s, Colour(0.6f * colour));
  }
}

// The legend, in the corner of the plotting area that covers the fewest points.
void drawLegend(Image& image, const Plot& plot, const Layout& L) {
  const PlotFrame& f = L.frame;
  const int s = L.scale, pad = L.pad, sampleWidth = 12 * s, rowHeight = L.lineHeight + s;
  std::vector<size_t> entries;
  std::vector<std::string> texts;
  for (size_t i = 0; i < plot.series.size(); ++i) {
    const PlotSeries& series = plot.series[i];
    if (series.label.empty()) continue;
    entries.push_back(i);
    texts.push_back(series.label + (f.hasY2 ? (series.axis == 1 ? " (right)" : " (left)") : ""));
  }
  if (entries.empty()) return;
  const int boxWidth = 3 * pad + sampleWidth + widest(texts, s);
  const int boxHeight = 2 * pad + static_cast<int>(entries.size()) * rowHeight - s;
  const int inset = 2 * pad;
  const Eigen::Vector2i corners[4] = {{f.right - inset - boxWidth, f.top + inset},
                                      {f.left + inset, f.top + inset},
                                      {f.right - inset - boxWidth, f.bottom - inset - boxHeight},
                                      {f.left + inset, f.bottom - inset - boxHeight}};
  int best = 0;
  size_t fewest = SIZE_MAX;
  for (int c = 0; c < 4; ++c) {
    size_t covered = 0;
    for (const PlotSeries& series : plot.series)
      for (const Eigen::Vector2d& p : seriesPixels(f, series))
        covered += p.x() >= corners[c].x() - pad && p.x() <= corners[c].x() + boxWidth + pad &&
                   p.y() >= corners[c].y() - pad && p.y() <= corners[c].y() + boxHeight + pad;
    if (covered < fewest) {
      fewest = covered;
      best = c;
    }
  }
  const int x0 = std::max(corners[best].x(), 0), y0 = std::max(corners[best].y(), 0);
  const int x1 = std::min(x0 + boxWidth, image.width() - 1), y1 = std::min(y0 + boxHeight, image.height() - 1);
  for (int y = y0; y <= y1; ++y)
    for (int x = x0; x <= x1; ++x)
      image.at(x, y) = opaque(x == x0 || x == x1 || y == y0 || y == y1 ? kLegendBorder : Colour(1, 1, 1));
  for (size_t e = 0; e < entries.size(); ++e) {
    const PlotSeries& series = plot.series[entries[e]];
    const int top = y0 + pad + static_cast<int>(e) * rowHeight;
    const double cy = top + 0.5 * kAscent * s - 0.5;
    Mask mask(image.width(), image.height(), x0 + 1, y0 + 1, x1 - 1, y1 - 1);
    if (series.lines) mask.segment({x0 + pad, cy}, {x0 + pad + sampleWidth, cy}, series.lineWidth);
    if (series.markers) mask.disc({x0 + pad + 0.5 * sampleWidth, cy}, series.markerSize);
    mask.paint(image, seriesColour(plot, entries[e]));
    putText(image, texts[e], x0 + 2 * pad + sampleWidth, top, s, kInk);
  }
}

}  // namespace

double AxisRange::fraction(double v) const {
  if (!usable(v, log)) return kNaN;
  return (toAxis(v, log) - toAxis(lo, log)) / (toAxis(hi, log) - toAxis(lo, log));
}

Eigen::Vector2d PlotFrame::toPixel(double px, double py, int axis) const {
  const AxisRange& yRange = axis == 1 ? y2 : y;
  return {left + x.fraction(px) * (right - left), bottom - yRange.fraction(py) * (bottom - top)};
}

PlotFrame plotFrame(const Plot& plot) { return layout(plot).frame; }

Image renderPlot(const Plot& plot) {
  const Layout L = layout(plot);
  const PlotFrame& f = L.frame;
  Image image(plot.width, plot.height, Eigen::Vector4f(1, 1, 1, 1));  // sRGB values until the end
  if (plot.grid) {
    for (double v : L.xTicks)
      if (const double px = std::round(f.toPixel(v, f.y.lo).x()); px > f.left && px < f.right)
        for (int y = f.top; y <= f.bottom; ++y) image.at(static_cast<int>(px), y) = opaque(kGridColour);
    for (double v : L.yTicks)
      if (const double py = std::round(f.toPixel(f.x.lo, v).y()); py > f.top && py < f.bottom)
        for (int x = f.left; x <= f.right; ++x) image.at(x, static_cast<int>(py)) = opaque(kGridColour);
  }
  for (size_t i = 0; i < plot.series.size(); ++i) drawSeries(image, f, plot.series[i], seriesColour(plot, i));
  for (size_t i = 0; i < plot.series.size(); ++i)
    drawPointLabels(image, f, plot.series[i], seriesColour(plot, i), L.scale);
  drawAxes(image, plot, L);
  if (plot.legend) drawLegend(image, plot, L);
  for (int y = 0; y < image.height(); ++y)
    for (int x = 0; x < image.width(); ++x)
      for (int c = 0; c < 3; ++c) image.at(x, y)[c] = srgbToLinear(image.at(x, y)[c]);
  return image;
}


std::vector<double> niceTicks(double lo, double hi, int target) {
  if (!std::isfinite(lo) || !std::isfinite(hi) || target < 1) return {};
  if (lo > hi) std::swap(lo, hi);
  const double raw = hi / target - lo / target;  // the span, without overflow
  if (!(raw > 1e-300)) return {lo};
  int k = static_cast<int>(std::floor(std::log10(raw)));
  const double n = raw / pow10(k);  // in [1, 10)
  int m = n < std::sqrt(2.0) ? 1 : n < std::sqrt(10.0) ? 2 : n < std::sqrt(50.0) ? 5 : 10;
  if (m == 10) {
    m = 1;
    ++k;
  }
  // Tick i is i m 10^k; an exact integer times or over an exact power of ten rounds once.
  const double unit = pow10(std::abs(k));
  const auto tick = [&](double i) { return k >= 0 ? i * m * unit : i * m / unit; };
  const double first = std::ceil(lo / tick(1) - 1e-9), last = std::floor(hi / tick(1) + 1e-9);
  std::vector<double> ticks;
  for (double j = 0; j <= std::min(last - first, 1000.0); ++j) ticks.push_back(tick(first + j) + 0.0);  // -0 -> 0
  return ticks.size() >= 2 || target > 1000 ? ticks : niceTicks(lo, hi, 2 * target);  // a smaller step
}

std::vector<double> logTicks(double lo, double hi, int target) {
  if (!std::isfinite(lo) || !std::isfinite(hi) || !(lo > 0) || !(hi > 0) || target < 1) return {};
  if (lo > hi) std::swap(lo, hi);
  const int k0 = static_cast<int>(std::ceil(std::log10(lo) - 1e-9));
  const int k1 = static_cast<int>(std::floor(std::log10(hi) + 1e-9));
  std::vector<double> ticks;
  if (k1 > k0) {  // decades, every n-th one
    const int every = (k1 - k0 + target - 1) / target;
    for (int k = static_cast<int>(std::ceil(double(k0) / every)) * every; k <= k1; k += every) ticks.push_back(pow10(k));
  }
  if (ticks.size() < 2) {
    ticks.clear();
    for (int k = static_cast<int>(std::floor(std::log10(lo))); k <= k1; ++k)
      for (int m : {1, 2, 5})
        if (const double v = k >= 0 ? m * pow10(k) : m / pow10(-k); v >= lo * (1 - 1e-9) && v <= hi * (1 + 1e-9))
          ticks.push_back(v);
  }
  if (ticks.size() < 2) ticks = niceTicks(lo, hi, target);
  std::erase_if(ticks, [](double v) { return !(v > 0); });
  return ticks;
}

std::vector<std::string> tickLabels(const std::vector<double>& ticks, bool log) {
  double maxAbs = 0.0, minAbs = std::numeric_limits<double>::infinity();
  for (double t : ticks) {
    maxAbs = std::max(maxAbs, std::fabs(t));
    if (t != 0.0) minAbs = std::min(minAbs, std::fabs(t));
  }
  const bool scientific = log ? (minAbs < 1e-3 || maxAbs >= 1e5) : (maxAbs >= 1e5 || maxAbs < 1e-3);
  const double step = ticks.size() > 1 ? std::fabs(ticks[1] - ticks[0]) : maxAbs;
  const auto exponent = [](double v) { return static_cast<int>(std::floor(std::log10(v) + 1e-9)); };
  std::vector<std::string> labels;
  char text[64];
  for (double t : ticks) {
    const double unit = log ? std::fabs(t) : step;  // the last digit that matters
    const int last = unit > 0.0 && std::isfinite(unit) ? exponent(unit) : 0;
    if (!std::isfinite(t)) {
      std::snprintf(text, sizeof text, "%g", t);
    } else if (scientific && t != 0.0) {
      const int e = exponent(std::fabs(t));
      std::snprintf(text, sizeof text, "%.*fe%d", std::max(0, e - last), t / pow10(e), e);
    } else if (scientific) {
      std::snprintf(text, sizeof text, "0");
    } else {
      std::snprintf(text, sizeof text, "%.*f", std::max(0, -last), t);
    }
    labels.emplace_back(text);
  }
  return labels;
}

Eigen::Vector3f plotColour(int index) {
  static const Eigen::Vector3f palette[10] = {
      {0.122f, 0.467f, 0.706f}, {1.000f, 0.498f, 0.055f}, {0.173f, 0.627f, 0.173f}, {0.839f, 0.153f, 0.157f},
      {0.580f, 0.404f, 0.741f}, {0.549f, 0.337f, 0.294f}, {0.890f, 0.467f, 0.761f}, {0.498f, 0.498f, 0.498f},
      {0.737f, 0.741f, 0.133f}, {0.090f, 0.745f, 0.812f}};
  return palette[((index % 10) + 10) % 10];
}

Eigen::Vector2i textSize(const std::string& text, int scale) {
  if (scale < 1) throw std::invalid_argument("text scale must be >= 1");
  const int n = static_cast<int>(text.size());
  return {n == 0 ? 0 : (n * kAdvance - 1) * scale, kGlyphRows * scale};
}

void drawText(Image& image, const std::string& text, int x, int y, int scale, const Eigen::Vector3f& colour) {
  textSize(text, scale);  // checks the scale
  putText(image, text, x, y, scale,
          Eigen::Vector4f(srgbToLinear(colour.x()), srgbToLinear(colour.y()), srgbToLinear(colour.z()), 1.0f));
}

}  // namespace kurage::render
