#include "pipeline/analysis/series.h"

#include <cmath>

namespace kurage::pipeline {

double interpolateSeries(const std::vector<SeriesPoint>& series, double x) {
  if (series.empty()) return 0.0;
  if (x <= series.front().x) return series.front().y;
  for (size_t i = 1; i < series.size(); ++i)
    if (series[i].x >= x) {
      const double f = (x - series[i - 1].x) / (series[i].x - series[i - 1].x);
      return series[i - 1].y + f * (series[i].y - series[i - 1].y);
    }
  return series.back().y;
}

SeriesError meanRelativeError(const std::vector<SeriesPoint>& measured, const std::vector<SeriesPoint>& reference) {
  SeriesError e;
  if (measured.empty()) return e;
  const double last = measured.back().x;
  for (const SeriesPoint& r : reference) {
    if (r.x > last * (1.0 + 1e-9)) continue;
    e.meanRelative += std::fabs(interpolateSeries(measured, r.x) - r.y) / r.y;
    ++e.points;
  }
  if (e.points) e.meanRelative /= e.points;
  return e;
}

}  // namespace kurage::pipeline
