// Series of measured points (x, y) against a reference series: linear interpolation and the mean
// relative error over the reference points the measurement covers. Dimensionless; the callers
// say what x and y are (pipeline/analysis/dam_break.h: Martin & Moyce's T, Z and tau, H).
#pragma once

#include <vector>

namespace kurage::pipeline {

struct SeriesPoint {
  double x = 0.0, y = 0.0;
};

// y at x, linear between the points (sorted by x), the end values outside them.
double interpolateSeries(const std::vector<SeriesPoint>& series, double x);

struct SeriesError {
  double meanRelative = 0.0;  // mean of |measured(x) - y| / y over the reference points used
  int points = 0;             // reference points inside the measured range of x
};
// Compares `measured` (sorted by x) with each reference point whose x lies within the measured
// range; points beyond it (a run shorter than the experiment) are left out and not counted.
SeriesError meanRelativeError(const std::vector<SeriesPoint>& measured, const std::vector<SeriesPoint>& reference);

}  // namespace kurage::pipeline
