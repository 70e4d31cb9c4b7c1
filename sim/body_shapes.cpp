#include "sim/body_shapes.h"

#include "sim/setup.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace kurage::sim {

namespace {

// A filled block: lattice points half a spacing inside [min, max] (the fluid blocks' rule).
BodyPoints boxPoints(const BodyParams& body, float s) {
  BodyPoints out;
  out.positions = latticePoints(FluidBlock{body.min, body.max}, s);
  out.edge.assign(out.positions.size(), std::numeric_limits<float>::infinity());
  return out;
}

// A sheet in x and y over [min, max], `layers` layers one spacing apart centred on the mid-plane.
// A particle's edge distance is its row counted from the sheet's border (0 on the border).
BodyPoints membranePoints(const BodyParams& body, float s) {
  BodyPoints out;
  const int nx = std::max(0, int(std::floor((body.max.x() - body.min.x()) / s + 1e-4f)));
  const int ny = std::max(0, int(std::floor((body.max.y() - body.min.y()) / s + 1e-4f)));
  const float midZ = 0.5f * (body.min.z() + body.max.z());
  for (int k = 0; k < body.layers; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        out.positions.emplace_back(body.min.x() + (i + 0.5f) * s, body.min.y() + (j + 0.5f) * s,
                                   midZ + (k - 0.5f * (body.layers - 1)) * s);
        const int edge = std::min({i, j, nx - 1 - i, ny - 1 - j});
        out.edge.push_back(float(edge));
      }
  return out;
}

// A spherical cap about `axis`: layer k has radius inner + k s; on each layer, rings of latitude
// one spacing apart along the sphere from the apex to the opening angle, each ring with as many
// particles as fit at one spacing. A particle's edge distance is its ring's arc length from the
// opening on the inner layer, in spacings (0 on the last ring).
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
      const float fromEdge = (edge - polar * body.innerRadius) / s;
      for (int n = 0; n < count; ++n) {
        const float phi = 2 * std::numbers::pi_v<float> * (n + 0.5f * (j % 2)) / float(count);
        const Eigen::Vector3f dir = std::cos(polar) * axis + std::sin(polar) * (std::cos(phi) * u + std::sin(phi) * v);
        out.positions.push_back(body.center + radius * dir);
        out.edge.push_back(fromEdge);
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
    out.edge.push_back(k == 0 ? 0.0f : std::numeric_limits<float>::infinity());
  }
  return out;
}

}  // namespace

BodyPoints bodyPoints(const BodyParams& body, float fluidSpacing) {
  const float s = body.spacingMetres(fluidSpacing);
  BodyPoints points;
  switch (body.shape) {
    case BodyShape::Box: points = boxPoints(body, s); break;
    case BodyShape::Membrane: points = membranePoints(body, s); break;
    case BodyShape::Shell: points = shellPoints(body, s); break;
    case BodyShape::Chain: points = chainPoints(body, s); break;
  }
  points.rimWidth = body.rimWidth;
  return points;
}

bool selected(const Selection& selection, const BodyPoints& points, size_t k) {
  switch (selection.kind) {
    case SelectionKind::All: return true;
    case SelectionKind::Rim:
      return points.edge[k] < std::max(selection.width > 0.0f ? selection.width : points.rimWidth, 1.0f) - 1e-4f;
    case SelectionKind::Region:
      return (points.positions[k].array() >= selection.min.array()).all() &&
             (points.positions[k].array() <= selection.max.array()).all();
  }
  return false;
}

}  // namespace kurage::sim
