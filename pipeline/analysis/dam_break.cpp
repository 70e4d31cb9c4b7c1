#include "pipeline/analysis/dam_break.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>

namespace kurage::pipeline {

MartinMoyce loadMartinMoyce(const std::filesystem::path& csv) {
  std::ifstream in(csv);
  if (!in) throw std::runtime_error(csv.string() + ": cannot open the Martin & Moyce data");
  MartinMoyce data;
  std::string line;
  int lineNumber = 0;
  while (std::getline(in, line)) {
    ++lineNumber;
    if (line.empty() || line[0] == '#' || line.rfind("series", 0) == 0) continue;
    std::stringstream fields(line);
    std::string series, xText, yText;
    std::getline(fields, series, ',');
    std::getline(fields, xText, ',');
    std::getline(fields, yText, ',');
    SeriesPoint p;
    try {
      p = {std::stod(xText), std::stod(yText)};
    } catch (const std::exception&) {
      throw std::runtime_error(csv.string() + ":" + std::to_string(lineNumber) + ": expected series,x,y");
    }
    if (series == "surge_front") data.surgeFront.push_back(p);
    else if (series == "column_height") data.columnHeight.push_back(p);
    else throw std::runtime_error(csv.string() + ":" + std::to_string(lineNumber) + ": unknown series " + series);
  }
  if (data.surgeFront.empty() || data.columnHeight.empty())
    throw std::runtime_error(csv.string() + ": no surge_front or column_height rows");
  return data;
}

DamBreakTrack::DamBreakTrack(const DamBreakGeometry& geometry) : g_(geometry) {
  if (!(g_.width > 0.0 && g_.height > 0.0 && g_.gravity > 0.0 && g_.spacing > 0.0))
    throw std::invalid_argument("DamBreakTrack: width, height, gravity and spacing must be positive");
  front_.push_back({0.0, 1.0});
  column_.push_back({0.0, 1.0});
}

double DamBreakTrack::tau(double time) const { return time * std::sqrt(g_.gravity / g_.width); }
double DamBreakTrack::timeAtTau(double tau) const { return tau / std::sqrt(g_.gravity / g_.width); }

void DamBreakTrack::record(const sim::ParticleSet& s, double time) {
  const double a = g_.width, l = g_.spacing;
  xs_.clear();
  band_.clear();
  for (size_t i = 0; i < s.size(); ++i) {
    if (s.kind[i] != 0) continue;
    const double x = s.x[i] - g_.origin.x(), z = s.z[i] - g_.origin.z();
    if (z < 0.25 * a) xs_.push_back(float(x));
    if (x < 2 * l) band_.push_back({float(z), i});
  }
  std::sort(xs_.begin(), xs_.end());
  // The column: the highest particle of the band by the back wall that is not spray, i.e. has at
  // least kColumnNeighbours other fluid particles within two spacings.
  std::sort(band_.begin(), band_.end(), [](const auto& u, const auto& v) { return u.first > v.first; });
  double column = -1e30;
  const float reach2 = float(4.0 * l * l);
  for (const auto& [z, i] : band_) {
    int near = 0;
    for (size_t j = 0; j < s.size() && near < kColumnNeighbours; ++j) {
      if (j == i || s.kind[j] != 0) continue;
      const float dx = s.x[j] - s.x[i], dy = s.y[j] - s.y[i], dz = s.z[j] - s.z[i];
      near += dx * dx + dy * dy + dz * dz < reach2;
    }
    if (near >= kColumnNeighbours) { column = z; break; }
  }
  const double x = xs_.empty() ? 0.0 : xs_[size_t(0.998 * double(xs_.size() - 1))];
  const double t = tau(time);
  front_.push_back({t * std::sqrt(2.0), (x + 0.5 * l) / a});  // T = t sqrt(2g/a)
  column_.push_back({t, column < -1e29 ? 0.0 : (column + 0.5 * l) / g_.height});
}

}  // namespace kurage::pipeline
