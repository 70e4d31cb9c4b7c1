#include "pipeline/report/svg_plot.h"

#include "pipeline/report/html.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

namespace kurage::pipeline {

namespace {

// Colours that stay apart for the colour-blind (Okabe & Ito 2008), then a second round darker.
const char* const kPalette[] = {"#0072B2", "#D55E00", "#009E73", "#CC79A7", "#E69F00",
                                "#56B4E9", "#000000", "#F0E442", "#004c7a", "#8f3f00"};

std::string colourOf(const PlotSeries& s, size_t k) {
  if (!std::isfinite(s.colour.x())) return kPalette[k % std::size(kPalette)];
  char buffer[16];
  auto byte = [](float v) { return int(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f)); };
  std::snprintf(buffer, sizeof buffer, "#%02x%02x%02x", byte(s.colour.x()), byte(s.colour.y()), byte(s.colour.z()));
  return buffer;
}

std::string px(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.1f", v);
  return buffer;
}

// One axis: its range after padding to ticks, and the map from values to pixels.
struct Scale {
  bool log = false;
  double lo = 0.0, hi = 1.0;      // in values (log: positive)
  double from = 0.0, to = 1.0;    // pixels of lo and hi
  std::vector<double> ticks;
  double step = 1.0;              // linear tick step (log: unused)
  bool empty = true;              // no data and no fixed limits

  double operator()(double v) const {
    const double t = log ? (std::log10(v) - std::log10(lo)) / (std::log10(hi) - std::log10(lo)) : (v - lo) / (hi - lo);
    return from + t * (to - from);
  }
  bool takes(double v) const { return std::isfinite(v) && (!log || v > 0.0); }
};

Scale makeScale(const PlotAxis& axis, const std::vector<double>& values, int tickCount) {
  Scale s;
  s.log = axis.log;
  double lo = INFINITY, hi = -INFINITY;
  for (double v : values)
    if (s.takes(v)) lo = std::min(lo, v), hi = std::max(hi, v);
  s.empty = !(lo <= hi);
  if (s.empty) lo = s.log ? 1.0 : 0.0, hi = s.log ? 10.0 : 1.0;
  if (std::isfinite(axis.min) && s.takes(axis.min)) lo = axis.min;
  if (std::isfinite(axis.max) && s.takes(axis.max)) hi = axis.max;
  if (std::isfinite(axis.min) || std::isfinite(axis.max)) s.empty = false;
  if (s.log) {
    if (!(hi > lo)) lo /= 2.0, hi *= 2.0;
    int a = int(std::floor(std::log10(lo) + 1e-9)), b = int(std::ceil(std::log10(hi) - 1e-9));
    if (b <= a) b = a + 1;
    if (!std::isfinite(axis.min)) lo = std::pow(10.0, a);
    if (!std::isfinite(axis.max)) hi = std::pow(10.0, b);
    const int stride = std::max(1, (b - a + 5) / 6);
    for (int e = a; e <= b; e += stride) {
      const double p = std::pow(10.0, e);
      for (double m : b - a < 2 ? std::vector<double>{1, 2, 5} : std::vector<double>{1})
        if (m * p >= lo * (1 - 1e-9) && m * p <= hi * (1 + 1e-9)) s.ticks.push_back(m * p);
    }
  } else {
    if (!(hi > lo)) {  // one value: a range around it (from 0 up for a 0)
      const double pad = lo != 0.0 ? 0.1 * std::fabs(lo) : 1.0;
      if (lo != 0.0) lo -= pad;
      hi += pad;
    }
    s.ticks = niceTicks(lo, hi, tickCount);
    // Counts (every value whole) get whole ticks.
    const bool whole = !values.empty() && std::all_of(values.begin(), values.end(), [](double v) {
      return !std::isfinite(v) || v == std::round(v);
    });
    if (whole && s.ticks.size() > 1 && s.ticks[1] - s.ticks[0] < 1.0) s.ticks = niceTicks(lo, hi, std::max(1, int(hi - lo)));
    s.step = s.ticks.size() > 1 ? s.ticks[1] - s.ticks[0] : hi - lo;
    if (!std::isfinite(axis.min)) lo = std::min(lo, s.ticks.front());
    if (!std::isfinite(axis.max)) hi = std::max(hi, s.ticks.back());
    s.ticks.erase(std::remove_if(s.ticks.begin(), s.ticks.end(),
                                 [&](double t) { return t < lo - 1e-9 * s.step || t > hi + 1e-9 * s.step; }),
                  s.ticks.end());
  }
  s.lo = lo;
  s.hi = hi;
  return s;
}

std::string logTickLabel(double v) {
  const double e = std::log10(v);
  if (std::fabs(e - std::round(e)) < 1e-9 && (e < -3 || e > 4)) return "1e" + std::to_string(int(std::round(e)));
  return formatNumber(v, 3);
}

}  // namespace

std::vector<double> niceTicks(double lo, double hi, int count) {
  const double raw = (hi - lo) / std::max(1, count);
  const double power = std::pow(10.0, std::floor(std::log10(raw)));
  double step = power;
  for (double m : {1.0, 2.0, 5.0, 10.0})
    if (m * power >= raw * (1 - 1e-9)) {
      step = m * power;
      break;
    }
  const double first = std::floor(lo / step + 1e-9) * step;
  std::vector<double> ticks;
  for (int i = 0;; ++i) {
    double t = first + i * step;
    if (std::fabs(t) < 1e-12 * step) t = 0.0;
    ticks.push_back(t);
    if (t >= hi - 1e-9 * step || i > 1000) break;
  }
  return ticks;
}

namespace {
double largestTick(const std::vector<double>& ticks) {
  double m = 0.0;
  for (double t : ticks) m = std::max(m, std::fabs(t));
  return m;
}
}  // namespace

std::string tickLabel(double value, double step, double largest) {
  if (std::fabs(value) < 1e-9 * step) return "0";
  // Plain decimals from a thousandth to a million ("0.015", "150", "370.5"), powers of ten beyond.
  if (step >= 1e-3 && std::max(largest, std::fabs(value)) < 1e6) {
    char buffer[48];
    std::snprintf(buffer, sizeof buffer, "%.*f", std::max(0, -int(std::floor(std::log10(step) + 1e-9))), value);
    return buffer;
  }
  const double magnitude = std::max(std::fabs(value), step);
  const int digits = std::max(1, int(std::floor(std::log10(magnitude) + 1e-9)) - int(std::floor(std::log10(step) + 1e-9)) + 1);
  return formatNumber(value, std::min(digits, 12));
}

std::string svgPlot(const Plot& plot, const std::string& id) {
  const double width = plot.width, height = plot.height;
  bool right = false;
  for (const PlotSeries& s : plot.series) right = right || s.axis == 1;
  const std::vector<std::string> title = wrapTitle(plot.title, size_t(std::max(20.0, (width - 20) / 7.5)));
  // The legend's entries, laid out in rows below the x axis label.
  struct Entry {
    size_t series;
    double x, y;
  };
  std::vector<Entry> legend;
  const double left = 64, rightMargin = right ? 64 : 20;
  double lx = left, rows = 0;
  if (plot.legend)
    for (size_t k = 0; k < plot.series.size(); ++k) {
      if (plot.series[k].label.empty()) continue;
      const double w = 30 + 6.6 * double(plot.series[k].label.size()) + 16;
      if (lx + w > width - 10 && lx > left) lx = left, ++rows;
      legend.push_back({k, lx, rows});
      lx += w;
    }
  const double legendHeight = legend.empty() ? 0 : 18 * (rows + 1) + 4;
  const double top = 14 + 17 * double(title.size()) + 8;
  const double bottom = 44 + legendHeight;
  const double plotW = std::max(40.0, width - left - rightMargin), plotH = std::max(40.0, height - top - bottom);

  std::vector<double> xs, ys, y2s;
  for (const PlotSeries& s : plot.series) {
    const size_t n = std::min(s.x.size(), s.y.size());
    xs.insert(xs.end(), s.x.begin(), s.x.begin() + long(n));
    (s.axis == 1 ? y2s : ys).insert((s.axis == 1 ? y2s : ys).end(), s.y.begin(), s.y.begin() + long(n));
  }
  Scale sx = makeScale(plot.x, xs, std::max(3, int(plotW / 90)));
  Scale sy = makeScale(plot.y, ys, std::max(3, int(plotH / 45)));
  Scale sy2 = makeScale(plot.y2, y2s, std::max(3, int(plotH / 45)));
  sx.from = left, sx.to = left + plotW;
  sy.from = sy2.from = top + plotH, sy.to = sy2.to = top;

  std::ostringstream o;
  o << "<svg xmlns=\"http://www.w3.org/2000/svg\" class=\"plot\" id=\"" << escapeHtml(id) << "\" viewBox=\"0 0 "
    << width << " " << height << "\" width=\"" << width << "\" height=\"" << height
    << "\" font-family=\"system-ui, sans-serif\" role=\"img\" aria-label=\"" << escapeHtml(plot.title) << "\">\n";
  o << "<rect width=\"100%\" height=\"100%\" fill=\"#fff\"/>\n";
  for (size_t i = 0; i < title.size(); ++i)
    o << "<text x=\"" << px(left) << "\" y=\"" << px(14 + 17 * double(i) + 4) << "\" font-size=\"14\" font-weight=\"600\" fill=\"#222\">"
      << escapeHtml(title[i]) << "</text>\n";
  // Grid and ticks.
  o << "<g class=\"axes\" font-size=\"11\" fill=\"#444\">\n";
  for (double t : sx.ticks) {
    const double x = sx(t);
    if (plot.grid) o << "<line x1=\"" << px(x) << "\" y1=\"" << px(top) << "\" x2=\"" << px(x) << "\" y2=\"" << px(top + plotH) << "\" stroke=\"#e6e6e6\"/>\n";
    o << "<text x=\"" << px(x) << "\" y=\"" << px(top + plotH + 16) << "\" text-anchor=\"middle\">"
      << escapeHtml(sx.log ? logTickLabel(t) : tickLabel(t, sx.step, largestTick(sx.ticks))) << "</text>\n";
  }
  for (double t : sy.ticks) {
    const double y = sy(t);
    if (plot.grid) o << "<line x1=\"" << px(left) << "\" y1=\"" << px(y) << "\" x2=\"" << px(left + plotW) << "\" y2=\"" << px(y) << "\" stroke=\"#e6e6e6\"/>\n";
    o << "<text x=\"" << px(left - 6) << "\" y=\"" << px(y + 4) << "\" text-anchor=\"end\">"
      << escapeHtml(sy.log ? logTickLabel(t) : tickLabel(t, sy.step, largestTick(sy.ticks))) << "</text>\n";
  }
  if (right)
    for (double t : sy2.ticks)
      o << "<text x=\"" << px(left + plotW + 6) << "\" y=\"" << px(sy2(t) + 4) << "\">"
        << escapeHtml(sy2.log ? logTickLabel(t) : tickLabel(t, sy2.step, largestTick(sy2.ticks))) << "</text>\n";
  o << "<rect x=\"" << px(left) << "\" y=\"" << px(top) << "\" width=\"" << px(plotW) << "\" height=\"" << px(plotH)
    << "\" fill=\"none\" stroke=\"#999\"/>\n";
  if (!plot.x.label.empty())
    o << "<text x=\"" << px(left + plotW / 2) << "\" y=\"" << px(top + plotH + 34) << "\" text-anchor=\"middle\" font-size=\"12\" fill=\"#222\">"
      << escapeHtml(plot.x.label) << "</text>\n";
  if (!plot.y.label.empty())
    o << "<text transform=\"translate(" << px(16) << " " << px(top + plotH / 2) << ") rotate(-90)\" text-anchor=\"middle\" font-size=\"12\" fill=\"#222\">"
      << escapeHtml(plot.y.label) << "</text>\n";
  if (right && !plot.y2.label.empty())
    o << "<text transform=\"translate(" << px(width - 12) << " " << px(top + plotH / 2) << ") rotate(90)\" text-anchor=\"middle\" font-size=\"12\" fill=\"#222\">"
      << escapeHtml(plot.y2.label) << "</text>\n";
  o << "</g>\n";
  if (sx.empty && sy.empty && sy2.empty)
    o << "<text x=\"" << px(left + plotW / 2) << "\" y=\"" << px(top + plotH / 2) << "\" text-anchor=\"middle\" font-size=\"12\" fill=\"#888\">no data</text>\n";

  // Series, clipped to the plot area.
  o << "<clipPath id=\"" << escapeHtml(id) << "-area\"><rect x=\"" << px(left - 4) << "\" y=\"" << px(top - 4)
    << "\" width=\"" << px(plotW + 8) << "\" height=\"" << px(plotH + 8) << "\"/></clipPath>\n";
  o << "<g clip-path=\"url(#" << escapeHtml(id) << "-area)\">\n";
  for (size_t k = 0; k < plot.series.size(); ++k) {
    const PlotSeries& s = plot.series[k];
    const Scale& ys2 = s.axis == 1 ? sy2 : sy;
    const std::string colour = colourOf(s, k);
    const double lineWidth = std::max(0.75, 0.8 * s.lineWidth);
    o << "<g class=\"series\" data-label=\"" << escapeHtml(s.label) << "\" fill=\"" << colour << "\">\n";
    const size_t n = std::min(s.x.size(), s.y.size());
    std::vector<std::vector<size_t>> runs(1);
    for (size_t i = 0; i < n; ++i) {
      if (!sx.takes(s.x[i]) || !ys2.takes(s.y[i])) {
        if (!runs.back().empty()) runs.emplace_back();
        continue;
      }
      runs.back().push_back(i);
    }
    if (runs.back().empty()) runs.pop_back();
    for (const std::vector<size_t>& run : runs) {
      if (s.lines) {
        o << "<polyline fill=\"none\" stroke=\"" << colour << "\" stroke-width=\"" << px(lineWidth)
          << "\" stroke-linejoin=\"round\" points=\"";
        for (size_t j = 0; j < run.size(); ++j) o << (j ? " " : "") << px(sx(s.x[run[j]])) << "," << px(ys2(s.y[run[j]]));
        o << "\"/>\n";
      }
      // A point alone on its line would not show: it gets a marker.
      if (s.markers || run.size() == 1)
        for (size_t i : run)
          o << "<circle cx=\"" << px(sx(s.x[i])) << "\" cy=\"" << px(ys2(s.y[i])) << "\" r=\"" << px(2.6 * s.markerSize) << "\"/>\n";
      for (size_t i : run)
        if (i < s.pointLabels.size() && !s.pointLabels[i].empty())
          o << "<text x=\"" << px(sx(s.x[i]) + 6) << "\" y=\"" << px(ys2(s.y[i]) - 5) << "\" font-size=\"10\" fill=\"#333\">"
            << escapeHtml(s.pointLabels[i]) << "</text>\n";
    }
    o << "</g>\n";
  }
  o << "</g>\n";
  if (!legend.empty()) {
    o << "<g class=\"legend\" font-size=\"12\" fill=\"#222\">\n";
    for (const Entry& e : legend) {
      const PlotSeries& s = plot.series[e.series];
      const std::string colour = colourOf(s, e.series);
      const double y = top + plotH + 44 + 18 * e.y + 8;
      if (s.lines)
        o << "<line x1=\"" << px(e.x) << "\" y1=\"" << px(y - 4) << "\" x2=\"" << px(e.x + 24) << "\" y2=\"" << px(y - 4)
          << "\" stroke=\"" << colour << "\" stroke-width=\"2.5\"/>\n";
      if (s.markers || !s.lines)
        o << "<circle cx=\"" << px(e.x + 12) << "\" cy=\"" << px(y - 4) << "\" r=\"3\" fill=\"" << colour << "\"/>\n";
      o << "<text x=\"" << px(e.x + 30) << "\" y=\"" << px(y) << "\">" << escapeHtml(s.label) << "</text>\n";
    }
    o << "</g>\n";
  }
  o << "</svg>\n";
  return o.str();
}

std::string svgBarChart(const std::string& title, const std::vector<SvgBar>& bars, const std::string& id, int width) {
  const double rowH = 22, top = 30, labelW = 190, textW = 150;
  const double height = top + rowH * double(bars.size()) + 10;
  const double barW = std::max(40.0, double(width) - labelW - textW);
  double most = 0.0;
  for (const SvgBar& b : bars) most = std::max(most, b.value);
  std::ostringstream o;
  o << "<svg xmlns=\"http://www.w3.org/2000/svg\" class=\"bars\" id=\"" << escapeHtml(id) << "\" viewBox=\"0 0 "
    << width << " " << height << "\" width=\"" << width << "\" height=\"" << height
    << "\" font-family=\"system-ui, sans-serif\" role=\"img\" aria-label=\"" << escapeHtml(title) << "\">\n";
  o << "<text x=\"0\" y=\"18\" font-size=\"14\" font-weight=\"600\" fill=\"#222\">" << escapeHtml(title) << "</text>\n";
  for (size_t i = 0; i < bars.size(); ++i) {
    const SvgBar& b = bars[i];
    const double y = top + rowH * double(i);
    const double w = most > 0 && b.value > 0 ? barW * b.value / most : 0.0;
    o << "<text x=\"" << px(labelW - 8) << "\" y=\"" << px(y + 15) << "\" text-anchor=\"end\" font-size=\"12\" fill=\"#222\">"
      << escapeHtml(b.label) << "</text>\n";
    o << "<rect class=\"bar\" data-value=\"" << formatNumber(b.value, 6) << "\" x=\"" << px(labelW) << "\" y=\"" << px(y + 3)
      << "\" width=\"" << px(std::max(w, 1.0)) << "\" height=\"" << px(rowH - 6) << "\" fill=\"" << kPalette[0] << "\"/>\n";
    o << "<text x=\"" << px(labelW + w + 6) << "\" y=\"" << px(y + 15) << "\" font-size=\"12\" fill=\"#444\">"
      << escapeHtml(b.text) << "</text>\n";
  }
  o << "</svg>\n";
  return o.str();
}

}  // namespace kurage::pipeline
