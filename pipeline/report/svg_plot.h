// Figures for the report pages (pipeline/report/run_report.h), drawn by kurage as inline SVG: the
// page needs no script, no network and no gnuplot. A line chart draws the same description as
// the gnuplot figures (pipeline/io/plot.h: title, axis labels, linear or log axes, fixed limits,
// a second y axis on the right, lines and markers, point labels, a legend below), so one Plot
// can go to either; a bar chart shows shares (where the time went).
//
// What the SVG holds, for readers and tests: each series is a <g class="series"> with its label
// in data-label; where it has lines, every drawn point is a vertex of exactly one of its
// <polyline>s (a value that is not finite, or not positive on a log axis, is skipped and ends the
// line); markers are <circle>s. Each bar is a <rect class="bar"> with its value in data-value.
// Ticks are 1, 2 or 5 times a power of ten (linear) or powers of ten (log, with 2 and 5 between
// them over less than two decades). All text is XML-escaped. Sizes are the Plot's pixels; the
// SVG scales to its container's width.
#pragma once

#include "pipeline/io/plot.h"

#include <string>
#include <vector>

namespace kurage::pipeline {

// About `count` ticks covering [lo, hi] at a step of 1, 2 or 5 times a power of ten; the first
// is at or below lo, the last at or above hi. lo < hi, both finite.
std::vector<double> niceTicks(double lo, double hi, int count);

// A tick's text: the fewest digits that tell ticks `step` apart ("0.25", "1500", "2e-5"); every
// tick of an axis whose `largest` |tick| reaches a million is a power-of-ten form ("5e5", "1e6").
std::string tickLabel(double value, double step, double largest);

// `plot` as an <svg> element; `id` becomes its id attribute (letters, digits, '-', '_').
std::string svgPlot(const Plot& plot, const std::string& id);

struct SvgBar {
  std::string label;
  double value = 0.0;  // bar length, in the chart's unit; negative values draw as 0
  std::string text;    // written after the bar (e.g. "12.3 s, 45 %")
};

// Horizontal bars, one row each, longest first as given (the caller orders them).
std::string svgBarChart(const std::string& title, const std::vector<SvgBar>& bars, const std::string& id,
                        int width = 560);

}  // namespace kurage::pipeline
