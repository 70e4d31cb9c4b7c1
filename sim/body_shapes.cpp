#include "sim/body_shapes.h"

#include "sim/setup.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace kurage::sim {

namespace {

// A filled block: lattice points half a spacing inside [min, max] (the fluid blocks' rule).
BodyPoints boxPoints(const BodyParams& body, float s) {
  BodyPoints out;
  out.positions = latticePoints(FluidBlock{body.min, body.max}, s);
  out.rim.assign(out.positions.size(), 0);
  return out;
}

// A sheet in x and y over [min, max], `layers` layers one spacing apart centred on the mid-plane.
// The rim is every particle within rim_width spacings of the sheet's edge.
BodyPoints membranePoints(const BodyParams& body, float s) {
  BodyPoints out;
  const int nx = std::max(0, int(std::floor((body.max.x() - body.min.x()) / s + 1e-4f)));
  const int ny = std::max(0, int(std::floor((body.max.y() - body.min.y()) / s + 1e-4f)));
  const float midZ = 0.5f * (body.min.z() + body.max.z());
  const int band = std::max(1, int(std::lround(body.rimWidth)));
  for (int k = 0; k < body.layers; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        out.positions.emplace_back(body.min.x() + (i + 0.5f) * s, body.min.y() + (j + 0.5f) * s,
                                   midZ + (k - 0.5f * (body.layers - 1)) * s);
        const int edge = std::min({i, j, nx - 1 - i, ny - 1 - j});
        out.rim.push_back(edge < band);
      }
  return out;
}

// A spherical cap about `axis`: layer k has radius inner + k s; on each layer, rings of latitude
// one spacing apart along the sphere from the apex to the opening angle, each ring with as many
// particles as fit at one spacing. The rim is the band within rim_width spacings of the edge.
BodyPoints shellPoints(const BodyParams& body, float s) {
  BodyPoints out;
  const Eigen::Vector3f axis = body.axis.normalized();
  const Eigen::Vector3f u = axis.unitOrthogonal();
  const Eigen::Vector3f v = axis.cross(u);
  const float theta = body.openingAngle * std::numbers::pi_v<float> / 180.0f;
  const float edge = theta * body.innerRadius;  // arc length of the rim on the inner layer
  const int rings = int(std::floor(edge / s + 1e-4f));  // the inner layer's rings, kept on every layer
  for (int k = 0; k < body.layers; ++k) {
    const float radius = body.innerRadius + k * s;
    for (int j = 0; j <= rings; ++j) {
      // Rings at the same polar angles on every layer, so the layers stack radially.
      const float polar = (edge - (rings - j) * s) / body.innerRadius;
      if (polar < -1e-6f) continue;
      const float ringRadius = radius * std::sin(std::max(polar, 0.0f));
      const int count = ringRadius < 0.5f * s ? 1 : std::max(3, int(std::lround(2 * std::numbers::pi_v<float> * ringRadius / s)));
      const bool rim = (edge - polar * body.innerRadius) < body.rimWidth * s - 1e-4f * s;
      for (int n = 0; n < count; ++n) {
        const float phi = 2 * std::numbers::pi_v<float> * (n + 0.5f * (j % 2)) / float(count);
        const Eigen::Vector3f dir = std::cos(polar) * axis + std::sin(polar) * (std::cos(phi) * u + std::sin(phi) * v);
        out.positions.push_back(body.center + radius * dir);
        out.rim.push_back(rim);
      }
    }
  }
  return out;
}

// Points from start to end one spacing apart (the last at most a spacing short of `end`); the
// rim of a chain is its first particle, where it hangs.
BodyPoints chainPoints(const BodyParams& body, float s) {
  BodyPoints out;
  const Eigen::Vector3f d = body.end - body.start;
  const int count = int(std::floor(d.norm() / s + 1e-4f)) + 1;
  const Eigen::Vector3f step = d.norm() > 0.0f ? Eigen::Vector3f(d.normalized() * s) : Eigen::Vector3f::Zero();
  for (int k = 0; k < count; ++k) {
    out.positions.push_back(body.start + float(k) * step);
    out.rim.push_back(k == 0);
  }
  return out;
}

}  // namespace

BodyPoints bodyPoints(const BodyParams& body, float fluidSpacing) {
  const float s = body.spacingMetres(fluidSpacing);
  switch (body.shape) {
    case BodyShape::Box: return boxPoints(body, s);
    case BodyShape::Membrane: return membranePoints(body, s);
    case BodyShape::Shell: return shellPoints(body, s);
    case BodyShape::Chain: return chainPoints(body, s);
  }
  return {};
}

bool selected(const Selection& selection, const BodyPoints& points, size_t k) {
  switch (selection.kind) {
    case SelectionKind::All: return true;
    case SelectionKind::Rim: return points.rim[k] != 0;
    case SelectionKind::Region:
      return (points.positions[k].array() >= selection.min.array()).all() &&
             (points.positions[k].array() <= selection.max.array()).all();
  }
  return false;
}

}  // namespace kurage::sim
