#include "pipeline/analysis/still_tank.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace kurage::pipeline {

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

namespace {
// The level where the colour field of `column` (heights above the floor and masses, sorted),
// averaged over `area`, is one half: c(z) = sum_j V_j Wbar(z - z_j) / area, V_j = m_j / rho0,
// Wbar the cubic spline (support h) integrated over a horizontal plane (header).
double colourLevel(const std::vector<std::pair<float, float>>& column, double area, double rho0, double h, double l) {
  if (column.empty() || !(area > 0.0)) return 0.0;
  const double perMass = 1.0 / (rho0 * area);
  const auto colour = [&](double z) {
    double c = 0.0;
    for (auto it = std::lower_bound(column.begin(), column.end(), std::make_pair(float(z - h), -1.0f));
         it != column.end() && it->first < z + h; ++it)
      c += it->second * projectedCubicSpline(z - it->first, h);
    return c * perMass;
  };
  // Down from above the highest particle, where the field vanishes, in steps of a quarter
  // spacing to the first height where it reaches one half; then bisection.
  double above = column.back().first + h, below = above;
  while (colour(below) < 0.5) {
    above = below;
    below -= 0.25 * l;
    if (below < -h) return 0.0;
  }
  for (int k = 0; k < 50 && above - below > 1e-9 * l; ++k) {
    const double mid = 0.5 * (above + below);
    (colour(mid) < 0.5 ? above : below) = mid;
  }
  return 0.5 * (above + below);
}
}  // namespace

double HydrostaticTrack::surfaceOf(const std::vector<std::pair<float, float>>& column) const {
  return colourLevel(column, area_, rho0_, h_, l_);
}

double waterLevel(const sim::SimParams& params, const sim::ParticleSet& p) {
  std::vector<std::pair<float, float>> column;
  for (size_t i = 0; i < p.size(); ++i)
    if (p.kind[i] == 0) column.emplace_back(p.z[i] - params.container.min.z(), p.mass[i]);
  std::sort(column.begin(), column.end());
  const Eigen::Vector3f size = params.container.max - params.container.min;
  return colourLevel(column, double(size.x()) * double(size.y()), params.fluid.restDensity,
                     params.fluid.supportRadiusMetres(), params.fluid.spacing);
}

double bodiesDisplacement(const sim::SimParams& params, const sim::ParticleSet& p, double level) {
  const sim::ContainerParams& box = params.container;
  // The weight: 1 up to `full` beyond the contact distance, 0 from `reach`.
  const double full = params.fluid.spacing, reach = 2.0 * params.fluid.supportRadiusMetres();
  // Each body particle's fluid-contact distance as built.
  std::vector<std::pair<Eigen::Vector3f, float>> contacts;
  Eigen::Vector3f lo = Eigen::Vector3f::Constant(std::numeric_limits<float>::max()), hi = -lo;
  for (size_t i = 0; i < p.size(); ++i) {
    if (p.kind[i] == 0) continue;
    const size_t b = size_t(p.kind[i] - 1);
    const float contact = b < params.bodies.size() ? params.collisions.fluidContact * params.bodies[b].fluidContactScale *
                                                         params.bodies[b].spacingMetres(params.fluid.spacing)
                                                   : 0.0f;
    const float r = contact + float(reach);
    const Eigen::Vector3f x(p.x[i], p.y[i], p.z[i]);
    contacts.emplace_back(x, contact);
    lo = lo.cwiseMin((x.array() - r).matrix());
    hi = hi.cwiseMax((x.array() + r).matrix());
  }
  if (contacts.empty()) return 0.0;
  lo = lo.cwiseMax(box.min);
  hi = hi.cwiseMin(box.max);
  hi.z() = std::min(hi.z(), float(double(box.min.z()) + level));
  if ((hi.array() <= lo.array()).any()) return 0.0;
  // The cells of a grid of l/2 from the container's corner: each one's clearance, the least
  // distance of its centre beyond a body particle's contact distance (up to `reach`).
  const float s = 0.5f * params.fluid.spacing;
  const Eigen::Array3i first = ((lo - box.min).array() / s).floor().cast<int>();
  const Eigen::Array3i last = ((hi - box.min).array() / s).ceil().cast<int>() - 1;
  const Eigen::Array3i n = (last - first + 1).max(0);
  if ((n <= 0).any()) return 0.0;
  const float far = float(reach);
  std::vector<float> clearance(size_t(n.x()) * size_t(n.y()) * size_t(n.z()), far);
  auto cell = [&](int i, int j, int k) {
    return (size_t(k - first.z()) * size_t(n.y()) + size_t(j - first.y())) * size_t(n.x()) + size_t(i - first.x());
  };
  auto centre = [&](int c, int axis) { return box.min[axis] + (float(c) + 0.5f) * s; };
  for (const auto& [x, contact] : contacts) {
    const float r = contact + far;
    const Eigen::Array3i a = (((x.array() - r) - box.min.array()) / s - 0.5f).ceil().cast<int>().max(first);
    const Eigen::Array3i z = (((x.array() + r) - box.min.array()) / s - 0.5f).floor().cast<int>().min(last);
    for (int k = a.z(); k <= z.z(); ++k) {
      const float dz = centre(k, 2) - x.z();
      for (int j = a.y(); j <= z.y(); ++j) {
        const float dy = centre(j, 1) - x.y();
        for (int i = a.x(); i <= z.x(); ++i) {
          const float dx = centre(i, 0) - x.x(), d2 = dx * dx + dy * dy + dz * dz;
          float& c = clearance[cell(i, j, k)];
          if (d2 < (c + contact) * (c + contact)) c = std::sqrt(d2) - contact;
        }
      }
    }
  }
  // The weight: 1 up to `full` beyond the contact, falling linearly to 0 at `reach`.
  const float top = float(double(box.min.z()) + level);
  auto weight = [&](float c) { return c >= far ? 0.0 : c <= float(full) ? 1.0 : double(far - c) / double(far - float(full)); };
  double volume = 0.0, water = 0.0;
  for (int k = first.z(); k <= last.z(); ++k) {
    if (centre(k, 2) >= top) continue;
    for (int j = first.y(); j <= last.y(); ++j)
      for (int i = first.x(); i <= last.x(); ++i) volume += weight(clearance[cell(i, j, k)]);
  }
  volume *= double(s) * double(s) * double(s);
  for (size_t i = 0; i < p.size(); ++i) {
    if (p.kind[i] != 0) continue;
    const Eigen::Array3i c = ((Eigen::Array3f(p.x[i], p.y[i], p.z[i]) - box.min.array()) / s).floor().cast<int>();
    if ((c < first).any() || (c > last).any() || centre(c.z(), 2) >= top) continue;
    water += weight(clearance[cell(c.x(), c.y(), c.z())]) * double(p.mass[i]) / double(params.fluid.restDensity);
  }
  const Eigen::Vector3f floor = box.max - box.min;
  return (volume - water) / (double(floor.x()) * double(floor.y()));
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

}  // namespace kurage::pipeline
