#include "pipeline/measures.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <numbers>
#include <sstream>
#include <stdexcept>

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

KindExtent kindExtent(const sim::ParticleSet& p, int kind) {
  KindExtent e;
  for (size_t i = 0; i < p.size(); ++i)
    if (p.kind[i] == kind) {
      const Eigen::Vector3f x(p.x[i], p.y[i], p.z[i]);
      e.min = e.min.cwiseMin(x);
      e.max = e.max.cwiseMax(x);
      e.centre += x.cast<double>();
      ++e.count;
    }
  if (e.count) e.centre /= double(e.count);
  return e;
}

double freeSurfaceHeight(const sim::ParticleSet& p, double cx, double cy, double clear, float cellSize, float spacing) {
  std::map<std::pair<int, int>, float> top;
  for (size_t i = 0; i < p.size(); ++i) {
    if (p.kind[i] != 0) continue;
    const int cellX = int(std::floor(p.x[i] / cellSize)), cellY = int(std::floor(p.y[i] / cellSize));
    const double mx = (cellX + 0.5) * cellSize, my = (cellY + 0.5) * cellSize;
    if (std::hypot(mx - cx, my - cy) <= clear) continue;
    const auto key = std::make_pair(cellX, cellY);
    const auto it = top.find(key);
    if (it == top.end() || it->second < p.z[i]) top[key] = p.z[i];
  }
  double sum = 0.0;
  for (const auto& [key, z] : top) sum += z;
  return top.empty() ? 0.0 : sum / double(top.size()) + 0.5 * spacing;
}

double submergedFraction(const sim::ParticleSet& p, int kind, float fluidSpacing) {
  const KindExtent e = kindExtent(p, kind);
  if (e.count == 0) return 0.0;
  const double halfExtent = 0.5 * std::max(e.max.x() - e.min.x(), e.max.y() - e.min.y());
  const double surface =
      freeSurfaceHeight(p, e.centre.x(), e.centre.y(), halfExtent + 1.5 * fluidSpacing, fluidSpacing, fluidSpacing);
  size_t below = 0;
  for (size_t i = 0; i < p.size(); ++i) below += p.kind[i] == kind && p.z[i] < surface;
  return double(below) / double(e.count);
}

HydrostaticTrack::HydrostaticTrack(const sim::SimParams& params, double filledHeight)
    : l_(params.fluid.spacing), h_(params.fluid.supportRadiusMetres()), lo_(params.container.min),
      hi_(params.container.max), rho0_(params.fluid.restDensity), rho0g_(params.fluid.restDensity * params.gravity.norm()),
      g_(params.gravity.norm()),
      area_(double(hi_.x() - lo_.x() - 2 * h_) * double(hi_.y() - lo_.y() - 2 * h_)),
      filledHeight_(filledHeight) {}

bool HydrostaticTrack::interior(const sim::ParticleSet& p, size_t i) const {
  // Half-open, [lo + h, hi - h): a lattice whose rows fall on the edges puts exactly
  // (hi - lo - 2h) / l rows over that width, whatever h / l (weightAbove's floor area).
  return p.kind[i] == 0 && p.x[i] >= lo_.x() + h_ && p.x[i] < hi_.x() - h_ && p.y[i] >= lo_.y() + h_ &&
         p.y[i] < hi_.y() - h_;
}

namespace {
// The cubic spline kernel of support h integrated over a plane at distance s from its centre:
// 2 pi int_{|s|}^{h} r W(r) dr = (16 / h) F(|s| / h), F(q) = int_q^1 t f(t) dt with
// W = 8 / (pi h^3) f(r / h). It integrates to 1 over s, and on a lattice of layers l = h / 2
// apart sums to exactly 1 / l at a point midway between two layers.
double projectedCubicSpline(double s, double h) {
  const double q = std::fabs(s) / h;
  if (q >= 1.0) return 0.0;
  const double t = 1.0 - q;
  const double F = q >= 0.5 ? 0.5 * t * t * t * t - 0.4 * t * t * t * t * t
                            : 0.0875 - q * q * (0.5 - q * q * (1.5 - 1.2 * q));
  return 16.0 / h * F;
}
}  // namespace

void HydrostaticTrack::sortInterior(const sim::ParticleSet& p, std::vector<std::pair<float, float>>& out) const {
  out.clear();
  for (size_t i = 0; i < p.size(); ++i)
    if (interior(p, i)) out.emplace_back(p.z[i] - lo_.z(), p.mass[i]);
  std::sort(out.begin(), out.end());
}

double HydrostaticTrack::freeSurface(const sim::ParticleSet& p) const {
  std::vector<std::pair<float, float>> column;
  sortInterior(p, column);
  return surfaceOf(column);
}

double HydrostaticTrack::surfaceOf(const std::vector<std::pair<float, float>>& column) const {
  // The level where the interior's colour field, averaged over its floor area, is one half:
  // c(z) = sum_j V_j Wbar(z - z_j) / area over the interior particles, V_j = m_j / rho0, Wbar
  // the cubic spline (support h) integrated over a horizontal plane (header).
  if (column.empty() || !(area_ > 0.0)) return 0.0;
  const double perMass = 1.0 / (rho0_ * area_);
  const auto colour = [&](double z) {
    double c = 0.0;
    for (auto it = std::lower_bound(column.begin(), column.end(), std::make_pair(float(z - h_), -1.0f));
         it != column.end() && it->first < z + h_; ++it)
      c += it->second * projectedCubicSpline(z - it->first, h_);
    return c * perMass;
  };
  // Down from above the highest particle, where the field vanishes, in steps of a quarter
  // spacing to the first height where it reaches one half; then bisection.
  double above = column.back().first + h_, below = above;
  while (colour(below) < 0.5) {
    above = below;
    below -= 0.25 * l_;
    if (below < -h_) return 0.0;
  }
  for (int k = 0; k < 50 && above - below > 1e-9 * l_; ++k) {
    const double mid = 0.5 * (above + below);
    (colour(mid) < 0.5 ? above : below) = mid;
  }
  return 0.5 * (above + below);
}

void HydrostaticTrack::record(const sim::ParticleSet& p) {
  // The interior's particles by height, once a sample: the surface and the sums from the top
  // (weightAbove)
  sortInterior(p, interiorZ_);
  const double surface = surfaceOf(interiorZ_);
  surfaceSum_ += surface;
  ++samples_;
  const double H = filledHeight_;
  weightAbove_.assign(interiorZ_.size() + 1, 0.0);
  momentAbove_.assign(interiorZ_.size() + 1, 0.0);
  for (size_t k = interiorZ_.size(); k-- > 0;) {
    const double weight = double(interiorZ_[k].second) * g_;
    weightAbove_[k] = weightAbove_[k + 1] + weight;
    momentAbove_[k] = momentAbove_[k + 1] + weight * interiorZ_[k].first;
  }
  // Inside [2h, H - 2h]: a layer [k l, (k + 1) l) or a slab [2 k l, 2 (k + 1) l) wholly inside.
  auto inside = [&](int k, float thickness) {
    return k * thickness >= 2 * h_ - 1e-3f * l_ && (k + 1) * thickness <= H - 2 * h_ + 1e-3f * l_;
  };
  for (size_t i = 0; i < p.size(); ++i) {
    if (!interior(p, i)) continue;
    const float z = p.z[i] - lo_.z();
    const double depth = surface - z;
    const int layer = int(std::floor(z / l_)), k = int(std::floor(z / (2 * l_)));
    if (inside(layer, l_)) {
      Slab& s = layers_[layer];
      s.sum += p.pressure[i] / (rho0g_ * depth);
      ++s.count;
    }
    if (!inside(k, 2 * l_)) continue;
    Slab& s = slabs_[k];
    s.sum += p.pressure[i] / (rho0g_ * depth);
    ++s.count;
    Slab& f = filled_[k];
    f.sum += p.pressure[i] / (rho0g_ * (H - z));
    ++f.count;
    Carried& c = carried_[k];
    c.pressure += p.pressure[i];
    c.weight += weightAbove(z);
  }
}

double HydrostaticTrack::weightAbove(float z) const {
  // Wholly above: centres above z + l/2; the fraction (z_j + l/2 - z) / l of those within l/2.
  auto index = [&](float height) {
    return size_t(std::lower_bound(interiorZ_.begin(), interiorZ_.end(), std::make_pair(height, -1.0f)) - interiorZ_.begin());
  };
  const size_t from = index(z - 0.5f * l_), to = index(z + 0.5f * l_);
  const double window = weightAbove_[from] - weightAbove_[to], windowMoment = momentAbove_[from] - momentAbove_[to];
  const double partial = (windowMoment + window * (0.5 * l_ - z)) / l_;
  return area_ > 0.0 ? (weightAbove_[to] + partial) / area_ : 0.0;
}

double HydrostaticTrack::worstSlabAgainstWeight() const {
  double w = 0.0;
  for (const auto& [k, c] : carried_)
    if (c.weight > 0.0) w = std::max(w, std::fabs(c.pressure / c.weight - 1.0));
  return w;
}

double HydrostaticTrack::surfaceError() const {
  return samples_ == 0 ? 0.0 : std::fabs(surfaceSum_ / samples_ - filledHeight_) / filledHeight_;
}

double HydrostaticTrack::worst(const std::map<int, Slab>& slabs) {
  double w = 0.0;
  for (const auto& [k, s] : slabs) w = std::max(w, std::fabs(s.sum / double(s.count) - 1.0));
  return w;
}

double rmsSpeed(const sim::ParticleSet& p, int kind) {
  double v2 = 0.0;
  size_t n = 0;
  for (size_t i = 0; i < p.size(); ++i)
    if (p.kind[i] == kind) {
      v2 += p.vx[i] * p.vx[i] + p.vy[i] * p.vy[i] + p.vz[i] * p.vz[i];
      ++n;
    }
  return n == 0 ? 0.0 : std::sqrt(v2 / double(n));
}

MembraneLeak membraneLeak(const sim::ParticleSet& p, int kind, float fluidSpacing) {
  const float lowest = kindExtent(p, kind).min.z();
  MembraneLeak m;
  for (size_t i = 0; i < p.size(); ++i)
    if (p.kind[i] == 0) {
      ++m.fluid;
      m.leaked += p.z[i] < lowest - 0.5f * fluidSpacing;
    }
  return m;
}

MembraneLoad membraneLoad(const sim::ParticleSet& p, int kind, float supportRadius) {
  const float near = 0.7f * supportRadius;
  std::vector<size_t> fluid, sheet;
  for (size_t i = 0; i < p.size(); ++i) {
    if (p.kind[i] == 0) fluid.push_back(i);
    else if (p.kind[i] == kind) sheet.push_back(i);
  }
  auto d2 = [&](size_t i, size_t j) {
    const float dx = p.x[i] - p.x[j], dy = p.y[i] - p.y[j], dz = p.z[i] - p.z[j];
    return dx * dx + dy * dy + dz * dz;
  };
  std::vector<double> sheetPressure, fluidPressure;
  for (size_t j : sheet)
    if (std::any_of(fluid.begin(), fluid.end(), [&](size_t i) { return d2(i, j) < near * near; }))
      sheetPressure.push_back(p.pressure[j]);
  for (size_t i : fluid)
    if (std::any_of(sheet.begin(), sheet.end(), [&](size_t j) { return d2(i, j) < supportRadius * supportRadius; }))
      fluidPressure.push_back(p.pressure[i]);
  auto quantile = [](std::vector<double>& v, double q) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    return v[size_t(q * double(v.size() - 1))];
  };
  MembraneLoad m;
  m.sheetParticles = sheetPressure.size();
  m.fluidParticles = fluidPressure.size();
  m.sheetPressure90 = quantile(sheetPressure, 0.9);
  m.fluidPressure50 = quantile(fluidPressure, 0.5);
  return m;
}

ShellWall::ShellWall(const sim::BodyParams& shell, int kind, const sim::ParticleSet& p, float fluidSpacing)
    : kind_(kind), layers_(std::max(1, shell.layers)), spacing_(shell.spacingMetres(fluidSpacing)),
      axis_(shell.axis.cast<double>().normalized()) {
  const Eigen::Vector3d centre = shell.center.cast<double>();
  const double rimPolar = double(shell.openingAngle) * std::numbers::pi / 180.0;
  struct Entry {
    int64_t id;
    int8_t layer;
    uint8_t margin;
    Eigen::Vector3d at;
  };
  std::vector<Entry> entries;
  for (size_t i = 0; i < p.size(); ++i) {
    if (p.kind[i] != kind) continue;
    const Eigen::Vector3d d = Eigen::Vector3d(p.x[i], p.y[i], p.z[i]) - centre;
    const double r = d.norm();
    const int layer = std::clamp(int(std::lround((r - shell.innerRadius) / spacing_)), 0, layers_ - 1);
    const double polar = std::acos(std::clamp(d.dot(axis_) / std::max(r, 1e-12), -1.0, 1.0));
    entries.push_back({p.id[i], int8_t(layer), uint8_t(polar >= rimPolar - 0.25 * spacing_ / shell.innerRadius),
                       Eigen::Vector3d(p.x[i], p.y[i], p.z[i])});
  }
  std::sort(entries.begin(), entries.end(), [](const Entry& a, const Entry& b) { return a.id < b.id; });
  for (const Entry& e : entries) {
    sortedIds_.push_back(e.id);
    layer_.push_back(e.layer);
    margin_.push_back(e.margin);
    built_.push_back(e.at);
  }
}

double ShellWall::apexHeight(const sim::ParticleSet& p) const {
  double top = -std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < p.size(); ++i)
    if (p.kind[i] == kind_) top = std::max(top, double(p.z[i]));
  return top;
}

ShellWall::Shape ShellWall::shape(const sim::ParticleSet& p) const {
  Eigen::Vector3d margin = Eigen::Vector3d::Zero();
  std::vector<Eigen::Vector3d> points;
  size_t n = 0;
  for (size_t i = 0; i < p.size(); ++i) {
    if (p.kind[i] != kind_) continue;
    points.emplace_back(p.x[i], p.y[i], p.z[i]);
    const int k = indexOf(p.id[i]);
    if (k < 0 || !margin_[size_t(k)]) continue;
    margin += points.back();
    ++n;
  }
  Shape s;
  if (n == 0) return s;
  margin /= double(n);
  Eigen::Vector3d axis = centre(p) - margin;
  axis = axis.norm() > 0.0 ? Eigen::Vector3d(axis.normalized()) : axis_;
  double lo = std::numeric_limits<double>::infinity(), hi = -lo, wide = 0.0;
  for (const Eigen::Vector3d& x : points) {
    const Eigen::Vector3d d = x - margin;
    const double along = d.dot(axis);
    lo = std::min(lo, along);
    hi = std::max(hi, along);
    wide = std::max(wide, (d - along * axis).norm());
  }
  s.height = hi - lo;
  s.diameter = 2.0 * wide;
  return s;
}

double ShellWall::closestUnjoinedPair(const sim::ParticleSet& p, double joinedWithin) const {
  std::vector<std::pair<size_t, Eigen::Vector3d>> now;  // (position in sortedIds_, position)
  for (size_t i = 0; i < p.size(); ++i) {
    if (p.kind[i] != kind_) continue;
    const int k = indexOf(p.id[i]);
    if (k >= 0) now.emplace_back(size_t(k), Eigen::Vector3d(p.x[i], p.y[i], p.z[i]));
  }
  double closest = std::numeric_limits<double>::infinity();
  const double joined2 = joinedWithin * joinedWithin;
  for (size_t a = 0; a < now.size(); ++a)
    for (size_t b = a + 1; b < now.size(); ++b) {
      if ((built_[now[a].first] - built_[now[b].first]).squaredNorm() < joined2) continue;
      closest = std::min(closest, (now[a].second - now[b].second).norm());
    }
  return closest;
}

namespace {
// Distance between the segments [p0, p1] and [q0, q1] (clamped closest points; Ericson 2005, 5.1.9).
double segmentDistance(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1, const Eigen::Vector3d& q0,
                       const Eigen::Vector3d& q1) {
  const Eigen::Vector3d d1 = p1 - p0, d2 = q1 - q0, r = p0 - q0;
  const double a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r);
  double s = 0.0, t = 0.0;
  if (a <= 1e-18 && e <= 1e-18) return r.norm();
  if (a <= 1e-18) {
    t = std::clamp(f / e, 0.0, 1.0);
  } else {
    const double c = d1.dot(r);
    if (e <= 1e-18) {
      s = std::clamp(-c / a, 0.0, 1.0);
    } else {
      const double b = d1.dot(d2), denom = a * e - b * b;
      s = denom > 1e-18 ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
      t = (b * s + f) / e;
      if (t < 0.0) {
        t = 0.0;
        s = std::clamp(-c / a, 0.0, 1.0);
      } else if (t > 1.0) {
        t = 1.0;
        s = std::clamp((b - c) / a, 0.0, 1.0);
      }
    }
  }
  return ((p0 + s * d1) - (q0 + t * d2)).norm();
}
}  // namespace

double chainSelfApproach(const sim::ParticleSet& p, int kind) {
  std::vector<std::pair<int64_t, Eigen::Vector3d>> chain;
  for (size_t i = 0; i < p.size(); ++i)
    if (p.kind[i] == kind) chain.emplace_back(p.id[i], Eigen::Vector3d(p.x[i], p.y[i], p.z[i]));
  std::sort(chain.begin(), chain.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  double closest = std::numeric_limits<double>::infinity();
  for (size_t a = 0; a + 1 < chain.size(); ++a)
    for (size_t b = a + 2; b + 1 < chain.size(); ++b)
      closest = std::min(closest, segmentDistance(chain[a].second, chain[a + 1].second, chain[b].second,
                                                  chain[b + 1].second));
  return closest;
}

int ShellWall::indexOf(int64_t id) const {
  const auto it = std::lower_bound(sortedIds_.begin(), sortedIds_.end(), id);
  return it != sortedIds_.end() && *it == id ? int(it - sortedIds_.begin()) : -1;
}

Eigen::Vector3d ShellWall::centre(const sim::ParticleSet& p) const {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  double mass = 0.0;
  for (size_t i = 0; i < p.size(); ++i)
    if (p.kind[i] == kind_) {
      sum += double(p.mass[i]) * Eigen::Vector3d(p.x[i], p.y[i], p.z[i]);
      mass += double(p.mass[i]);
    }
  return mass > 0.0 ? Eigen::Vector3d(sum / mass) : sum;
}

double ShellWall::marginRadius(const sim::ParticleSet& p) const {
  // The margin's own centroid, so that a tilted bell keeps its margin radius.
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  std::vector<Eigen::Vector3d> ring;
  for (size_t i = 0; i < p.size(); ++i) {
    if (p.kind[i] != kind_) continue;
    const int k = indexOf(p.id[i]);
    if (k < 0 || !margin_[size_t(k)]) continue;
    ring.emplace_back(p.x[i], p.y[i], p.z[i]);
    c += ring.back();
  }
  if (ring.empty()) return 0.0;
  c /= double(ring.size());
  double sum = 0.0;
  for (const Eigen::Vector3d& x : ring) sum += (x - c).norm();
  return sum / double(ring.size());
}

double ShellWall::tiltDegrees(const sim::ParticleSet& p) const { return tiltDegrees(p, axis_); }

double ShellWall::tiltDegrees(const sim::ParticleSet& p, const Eigen::Vector3d& reference) const {
  Eigen::Vector3d margin = Eigen::Vector3d::Zero();
  size_t n = 0;
  for (size_t i = 0; i < p.size(); ++i) {
    if (p.kind[i] != kind_) continue;
    const int k = indexOf(p.id[i]);
    if (k < 0 || !margin_[size_t(k)]) continue;
    margin += Eigen::Vector3d(p.x[i], p.y[i], p.z[i]);
    ++n;
  }
  if (n == 0) return 0.0;
  const Eigen::Vector3d up = centre(p) - margin / double(n);
  if (!(up.norm() > 0.0)) return 0.0;
  return std::acos(std::clamp(up.normalized().dot(reference.normalized()), -1.0, 1.0)) * 180.0 / std::numbers::pi;
}

size_t ShellWall::fluidInsideWall(const sim::ParticleSet& p) const {
  if (layers_ < 2) return 0;
  // The innermost and outermost layers' particles in buckets of one spacing.
  const float cell = spacing_;
  const auto key = [cell](float x, float y, float z) {
    const auto c = [cell](float v) { return uint64_t(int64_t(std::floor(v / cell)) & 0x1fffff); };
    return (c(x) << 42) | (c(y) << 21) | c(z);
  };
  std::map<uint64_t, std::vector<std::pair<Eigen::Vector3f, int8_t>>> buckets;
  for (size_t i = 0; i < p.size(); ++i) {
    if (p.kind[i] != kind_) continue;
    const int k = indexOf(p.id[i]);
    if (k < 0) continue;
    const int8_t layer = layer_[size_t(k)];
    if (layer != 0 && layer != layers_ - 1) continue;
    buckets[key(p.x[i], p.y[i], p.z[i])].push_back({Eigen::Vector3f(p.x[i], p.y[i], p.z[i]), layer});
  }
  const float reach2 = spacing_ * spacing_;
  std::vector<Eigen::Vector3f> near[2];
  size_t inside = 0;
  for (size_t i = 0; i < p.size(); ++i) {
    if (p.kind[i] != 0) continue;
    const Eigen::Vector3f x(p.x[i], p.y[i], p.z[i]);
    near[0].clear();
    near[1].clear();
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const auto it = buckets.find(key(x.x() + dx * cell, x.y() + dy * cell, x.z() + dz * cell));
          if (it == buckets.end()) continue;
          for (const auto& [q, layer] : it->second)
            if ((q - x).squaredNorm() < reach2) near[layer == 0 ? 0 : 1].push_back(q - x);
        }
    // Between the layers: an inner and an outer particle on opposite sides of it.
    bool between = false;
    for (const Eigen::Vector3f& a : near[0])
      for (const Eigen::Vector3f& b : near[1]) between = between || a.dot(b) < 0.0f;
    inside += between;
  }
  return inside;
}

MetaballField::MetaballField(std::vector<Eigen::Vector3f> points, const render::MetaballParams& params)
    : points_(std::move(points)), params_(params) {
  if (points_.empty()) return;
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = -lo;
  for (const Eigen::Vector3f& q : points_) {
    centroid_ += q.cast<double>();
    lo = lo.cwiseMin(q.cast<double>());
    hi = hi.cwiseMax(q.cast<double>());
  }
  centroid_ /= double(points_.size());
  for (const Eigen::Vector3f& q : points_) reach_ = std::max(reach_, (q.cast<double>() - centroid_).norm());
  reach_ += params_.radius;
  const double r = params_.radius;
  lower_ = lo - Eigen::Vector3d::Constant(r);
  for (int a = 0; a < 3; ++a) cells_[a] = std::max(1, int(std::ceil((hi[a] + r - lower_[a]) / r)));
  const size_t cellCount = size_t(cells_.x()) * size_t(cells_.y()) * size_t(cells_.z());
  std::vector<uint32_t> cellOf(points_.size());
  cellStart_.assign(cellCount + 1, 0);
  for (size_t i = 0; i < points_.size(); ++i) {
    Eigen::Vector3i c;
    for (int a = 0; a < 3; ++a) c[a] = std::clamp(int((points_[i][a] - lower_[a]) / r), 0, cells_[a] - 1);
    cellOf[i] = uint32_t((size_t(c.z()) * size_t(cells_.y()) + size_t(c.y())) * size_t(cells_.x()) + size_t(c.x()));
    ++cellStart_[cellOf[i] + 1];
  }
  for (size_t c = 0; c < cellCount; ++c) cellStart_[c + 1] += cellStart_[c];
  cellPoints_.resize(points_.size());
  std::vector<uint32_t> fill(cellStart_.begin(), cellStart_.end() - 1);
  for (size_t i = 0; i < points_.size(); ++i) cellPoints_[fill[cellOf[i]]++] = uint32_t(i);
}

double MetaballField::operator()(const Eigen::Vector3d& x) const {
  if (points_.empty()) return 0.0;
  const double r = params_.radius, r2 = r * r;
  Eigen::Vector3i c;
  for (int a = 0; a < 3; ++a) c[a] = int(std::floor((x[a] - lower_[a]) / r));
  double f = 0.0;
  for (int k = c.z() - 1; k <= c.z() + 1; ++k)
    for (int j = c.y() - 1; j <= c.y() + 1; ++j)
      for (int i = c.x() - 1; i <= c.x() + 1; ++i) {
        if (i < 0 || j < 0 || k < 0 || i >= cells_.x() || j >= cells_.y() || k >= cells_.z()) continue;
        const size_t cell = (size_t(k) * size_t(cells_.y()) + size_t(j)) * size_t(cells_.x()) + size_t(i);
        for (uint32_t n = cellStart_[cell]; n < cellStart_[cell + 1]; ++n) {
          const double q = (points_[cellPoints_[n]].cast<double>() - x).squaredNorm() / r2;
          if (q < 1.0) f += params_.strength * (1.0 - q) * (1.0 - q);
        }
      }
  return f;
}

namespace {

// The outermost point along centre + s * direction, s in [0, far], where inside(s) turns true,
// marched inwards in steps of `step` and bisected to `tolerance`; negative when never inside.
template <class Inside>
double outermostCrossing(Inside inside, double far, double step, double tolerance) {
  double outside = far;
  if (inside(outside)) return -1.0;
  for (double s = far - step;; s -= step) {
    if (s < 0.0) s = 0.0;
    if (inside(s)) {
      double in = s, out = outside;
      while (out - in > tolerance) {
        const double mid = 0.5 * (in + out);
        (inside(mid) ? in : out) = mid;
      }
      return 0.5 * (in + out);
    }
    outside = s;
    if (s == 0.0) return -1.0;
  }
}

}  // namespace

SurfaceDistance surfaceDistance(const render::LevelSet& levelSet, const MetaballField& field,
                                const render::MetaballParams& params, int rays) {
  SurfaceDistance d;
  const double voxel = params.voxelSize;
  const double far = field.reach() + 2.0 * voxel;
  const double step = 0.1 * std::min<double>(params.radius, voxel);
  const double tolerance = 1e-6 * voxel;
  const Eigen::Vector3d c = field.centroid();
  double sum = 0.0, sumSquares = 0.0;
  const double golden = std::numbers::pi * (3.0 - std::sqrt(5.0));
  for (int k = 0; k < rays; ++k) {
    const double z = 1.0 - (2.0 * k + 1.0) / rays;
    const double rho = std::sqrt(std::max(0.0, 1.0 - z * z));
    const Eigen::Vector3d dir(rho * std::cos(golden * k), rho * std::sin(golden * k), z);
    const double exact = outermostCrossing([&](double s) { return field(c + s * dir) > params.threshold; }, far,
                                           step, tolerance);
    const double level = outermostCrossing(
        [&](double s) { return levelSet.sample((c + s * dir).cast<float>()) < 0.0f; }, far, step, tolerance);
    if (exact < 0.0 || level < 0.0) {
      d.misses += (exact < 0.0) != (level < 0.0);
      continue;
    }
    const double e = std::fabs(level - exact);
    sum += e;
    sumSquares += e * e;
    d.max = std::max(d.max, e);
    ++d.rays;
  }
  if (d.rays) {
    d.mean = sum / d.rays;
    d.rms = std::sqrt(sumSquares / d.rays);
  }
  return d;
}

double imageRmse(const render::Image& actual, const render::Image& reference) {
  if (actual.width() != reference.width() || actual.height() != reference.height())
    throw std::invalid_argument("imageRmse: the images differ in size");
  const size_t pixels = size_t(actual.width()) * size_t(actual.height());
  if (pixels == 0) return 0.0;
  double sum = 0.0;
  for (int y = 0; y < actual.height(); ++y)
    for (int x = 0; x < actual.width(); ++x)
      for (int c = 0; c < 3; ++c) {
        const double a = render::linearToSrgb(std::clamp(actual.at(x, y)[c], 0.0f, 1.0f));
        const double b = render::linearToSrgb(std::clamp(reference.at(x, y)[c], 0.0f, 1.0f));
        sum += (a - b) * (a - b);
      }
  return std::sqrt(sum / (3.0 * double(pixels)));
}

}  // namespace kurage::pipeline
