// Surfacing: turns particle positions into metaball level sets with OpenVDB, stores them as
// .vdb files, and meshes them for the tracer. It knows nothing of SPH: it takes positions.
//
// Metaball field (POV-Ray's blob component, which the paper's renders used):
//   f(x) = sum_i s * (1 - (|x - x_i| / R)^2)^2   for |x - x_i| < R, else 0
// The surface is the set f(x) = T (threshold). A single particle's surface is the sphere of
// radius R * sqrt(1 - sqrt(T / s)).
//
// The field is summed at the voxel centres of a sparse grid of the given voxel size (world units,
// metres), then turned into a narrow-band signed distance level set (negative inside,
// background = halfWidth * voxelSize) whose zero crossing is the surface f = T. Grids are named
// by material ("fluid", "bell", ...).
//
// How the distances are made (details in surfacing.cpp): the sign of every voxel is the sign of
// T - f at its centre, exactly. The magnitude is the distance to the nearest of a set of surface
// points: the crossings of f = T on the grid edges (linear interpolation of f) and one Newton
// step |f - T| / |grad f| from each voxel within a voxel of the surface; voxels next to the
// surface keep their own estimate where it is smaller. It is not an exact distance transform:
// against the analytic distance to a single blob's sphere, every band voxel is within 0.25
// voxel (test_surfacing: about 0.14 voxel worst for R = 2, T = 0.6, voxel 0.25 and 0.22 for
// R = 1, T = 0.2, voxel 0.1). Away from the surface the points are about a voxel apart, so
// distances there tend to be slightly too large; the zero crossing itself, between voxels of
// opposite sign, comes from their own estimates. The result is bit for bit the same for any
// thread count.
#pragma once

#include "render/mesh.h"

#include <Eigen/Core>

#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace kurage::render {

struct MetaballParams {
  float radius = 2.0f;     // R, metres
  float threshold = 0.6f;  // T, field units
  float strength = 1.0f;   // s, field units
  float voxelSize = 0.25f; // metres
  float halfWidth = 3.0f;  // narrow band half width, voxels
};

// Opaque handle on an OpenVDB float level set, so that callers need not include OpenVDB.
class LevelSet {
public:
  LevelSet();
  ~LevelSet();
  LevelSet(LevelSet&&) noexcept;
  LevelSet& operator=(LevelSet&&) noexcept;

  // True when there is no active voxel (also for a default-constructed level set).
  bool empty() const;
  // Metres; 0 for a default-constructed level set.
  float voxelSize() const;
  // Signed distance at a world position (trilinear); background outside the narrow band;
  // +infinity for a default-constructed level set.
  float sample(const Eigen::Vector3f& worldPosition) const;
  size_t activeVoxelCount() const;
  size_t memoryBytes() const;

  struct Impl;
  std::unique_ptr<Impl> impl;
};

// Builds the metaball level set of the given particle positions (world space, metres).
// An empty input yields an empty level set.
LevelSet buildMetaballLevelSet(const std::vector<Eigen::Vector3f>& positions, const MetaballParams& params);

// Meshes the zero crossing of the level set (OpenVDB volumeToMesh, triangulated) with
// per-vertex normals from the level set gradient.
TriangleMesh meshLevelSet(const LevelSet& levelSet);

// Writes named level sets into one .vdb file (temporary name, then rename), with string/float
// metadata per file (e.g. "frame", "time"). Throws std::runtime_error naming the path.
void writeLevelSets(const std::filesystem::path& path, const std::map<std::string, const LevelSet*>& grids,
                    double time, int frame);

// Reads every float grid of a .vdb file written by writeLevelSets, keyed by grid name.
// Throws std::runtime_error naming the path if the file is missing, truncated or not a VDB.
std::map<std::string, LevelSet> readLevelSets(const std::filesystem::path& path);

// The file metadata written by writeLevelSets ("kurage:time" seconds, "kurage:frame").
struct LevelSetFileInfo {
  double time = 0.0;
  int frame = 0;
};
// As above, and also returns the file metadata in *info (when not null; fields the file lacks
// keep their defaults).
std::map<std::string, LevelSet> readLevelSets(const std::filesystem::path& path, LevelSetFileInfo* info);

// Version string of the OpenVDB library in use (for run.json).
std::string openvdbVersion();

}  // namespace kurage::render
