// The dam break against Martin & Moyce (1952), "An experimental study of the collapse of liquid
// columns on a rigid horizontal plane", Phil. Trans. R. Soc. A 244: their surge-front and
// residual-column series, and a tracker that samples both from a simulation's particles.
//
// Units: metres and seconds unless a name says otherwise; the series are dimensionless, as
// Martin & Moyce give them: front Z = x / a against T = t sqrt(2 g / a), residual height
// H = h / (2a) against tau = t sqrt(g / a), a the column's width.
#pragma once

#include "pipeline/analysis/series.h"
#include "sim/particles.h"

#include <Eigen/Core>

#include <filesystem>
#include <utility>
#include <vector>

namespace kurage::pipeline {

// The two series of tests/data/martin_moyce_1952.csv (a copy of ../shared/data/).
struct MartinMoyce {
  std::vector<SeriesPoint> surgeFront;    // (T, Z)
  std::vector<SeriesPoint> columnHeight;  // (tau, H)
};
// Throws std::runtime_error naming the path if the file is missing or malformed.
MartinMoyce loadMartinMoyce(const std::filesystem::path& csv);

// A column of width a (along x from the back wall at origin.x) and initial height `height`
// standing on the floor z = origin.z, collapsing along +x under gravity g.
struct DamBreakGeometry {
  double width = 0.0;    // a, m
  double height = 0.0;   // initial column height (2a in Martin & Moyce), m
  double gravity = 0.0;  // |g|, m/s^2
  double spacing = 0.0;  // fluid particle spacing l, m
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();  // back wall x, floor z
};

// Samples the surge front and the residual column height of the fluid (kind 0) over time, as
// tests/test_dam_break.cpp and docs/results/validation.md define them: the front is the 99.8th
// percentile of x over particles below z = a / 4 (robust to isolated spray), plus half a
// spacing; the column height is the highest particle within two spacings of the back wall that has
// at least three other fluid particles within two spacings (not spray), plus half a spacing (0 when
// the band holds only spray). Both series start at (0, 1).
class DamBreakTrack {
public:
  explicit DamBreakTrack(const DamBreakGeometry& geometry);
  void record(const sim::ParticleSet& particles, double time);
  const std::vector<SeriesPoint>& front() const { return front_; }    // (T, Z)
  const std::vector<SeriesPoint>& column() const { return column_; }  // (tau, H)
  // tau = t sqrt(g / a) for a time in seconds, and back.
  double tau(double time) const;
  double timeAtTau(double tau) const;

private:
  DamBreakGeometry g_;
  std::vector<SeriesPoint> front_, column_;
  std::vector<float> xs_;
  std::vector<std::pair<float, size_t>> band_;  // (z, index) of the particles by the back wall
  static constexpr int kColumnNeighbours = 3;   // fewer within two spacings: spray, not the column
};

}  // namespace kurage::pipeline
