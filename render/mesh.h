// A triangle mesh in world space, as the surfacing stage produces it and the tracer consumes
// it. Normals are per vertex (unit length) for smooth shading; they may be empty, in which case
// the tracer shades with the geometric normal.
#pragma once

#include <Eigen/Core>

#include <vector>

namespace kurage::render {

struct TriangleMesh {
  std::vector<Eigen::Vector3f> positions;
  std::vector<Eigen::Vector3f> normals;  // empty or one per position
  std::vector<Eigen::Vector3i> triangles;  // counter-clockwise seen from outside
  bool operator==(const TriangleMesh&) const = default;
};

}  // namespace kurage::render
