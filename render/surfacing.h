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

#include "render/anisotropy.h"
#include "render/mesh.h"

#include <Eigen/Core>

#include <filesystem>
#include <functional>
#include <iosfwd>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace kurage::render {

// The shape of each particle's blob: the sphere of radius R above, or an ellipsoid that follows
// the particle's neighbourhood (render/anisotropy.h, Yu & Turk 2013) whose longest axis is R, with
// the same profile s (1 - q^2)^2 in the ellipsoid's own distance q.
enum class MetaballKernel { Isotropic, Anisotropic };

struct MetaballParams {
  float radius = 2.0f;     // R, metres
  float threshold = 0.6f;  // T, field units
  float strength = 1.0f;   // s, field units
  float voxelSize = 0.25f; // metres
  float halfWidth = 3.0f;  // narrow band half width, voxels
  MetaballKernel kernel = MetaballKernel::Isotropic;
  AnisotropyParams anisotropy;  // with MetaballKernel::Anisotropic
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

// Thrown by buildMetaballLevelSet when its stop check asked it to end.
class SurfacingStopped : public std::runtime_error {
public:
  SurfacingStopped() : std::runtime_error("surfacing stopped before the level set was finished") {}
};

// Builds the metaball level set of the given particle positions (world space, metres), with the
// kernel params.kernel. An empty input yields an empty level set. `stop`, when given, is asked
// between the passes (kernels, field, crossings, narrow band): true throws SurfacingStopped.
LevelSet buildMetaballLevelSet(const std::vector<Eigen::Vector3f>& positions, const MetaballParams& params,
                               const std::function<bool()>& stop = {});
// The same with each particle's blob scaled: radius R * radiusScales[i] (the ellipsoid's axes
// likewise), scales in (0, kMaxRadiusScale], one per position (empty: all 1; scales of at most 1
// with 1s give the same bits as the call above). Throws std::invalid_argument for a wrong count or
// a scale out of range.
constexpr float kMaxRadiusScale = 2.0f;
LevelSet buildMetaballLevelSet(const std::vector<Eigen::Vector3f>& positions, const std::vector<float>& radiusScales,
                               const MetaballParams& params, const std::function<bool()>& stop = {});

// Radius scales for particles that stand for more matter than as built: a particle whose rest
// density is restDensityFactors[i] times its rest density as built stands for 1 / factor times
// its volume, and its blob keeps that volume:
//   scale_i = clamp(factor_i^(-1/3), 1, kMaxRadiusScale).
// For a telescopic body's particle the factor is (L_i^leng)^3 (SPEC (8)-(10)), so the scale is
// its springs' stretch 1 / L_i^leng: the blobs spread as the particles do, and a body stretched
// uniformly by s surfaces as its rest surface scaled by s. (With blobs of radius R, a sheet
// stretched in its plane shows holes once its spacing passes about 1.1 R, a square lattice at
// T = s / 2, where the telescopic density still holds the fluid back.) Returns empty when every
// scale is 1 (unstretched or compressed particles keep R, bit for bit). Factors must be finite
// and > 0 (std::invalid_argument otherwise).
std::vector<float> stretchRadiusScales(const std::vector<float>& restDensityFactors);

// Intersects a level set with the inside of the axis-aligned box [boxMin, boxMax] (world space,
// metres): CSG on signed distances, phi' = max(phi, phi_box), phi_box the exact signed distance to
// the box (negative inside). Used to keep a fluid's surface inside its container: nothing of the
// result lies outside the box, and where the level set's inside reaches past a face, the face
// becomes the surface. The narrow band is rebuilt (every voxel within the half width of the new
// surface, taken from the old band and from the voxels near the box's faces that were inside) and
// flood-filled, so the result is again a valid narrow-band level set. max() is exact inside both
// sets and never farther than the true distance outside (at edges and corners of the cut it can
// be smaller). Bit for bit the same for any thread count. An empty level set stays empty; a box
// with boxMin > boxMax on an axis throws std::invalid_argument.
void intersectWithBox(LevelSet& levelSet, const Eigen::Vector3f& boxMin, const Eigen::Vector3f& boxMax);

// Meshes the zero crossing of the level set (OpenVDB volumeToMesh, triangulated) with
// per-vertex normals from the level set gradient.
TriangleMesh meshLevelSet(const LevelSet& levelSet);

// The file metadata of a level set file: "kurage:time" (seconds, double), "kurage:frame" (int32)
// and string entries `tags` (pipeline/io adds the stage, scene hash and checksum).
struct LevelSetFileInfo {
  double time = 0.0;
  int frame = 0;
  std::map<std::string, std::string> tags;
};

// Serialises named level sets (OpenVDB stream format, one float grid each) with the metadata.
// Files are written and read by pipeline/io (surface_file.h), which checks them first.
// Throws std::runtime_error on failure.
void writeLevelSets(std::ostream& out, const std::map<std::string, const LevelSet*>& grids,
                    const LevelSetFileInfo& info);

// Reads every float grid of a stream written by writeLevelSets, keyed by grid name, and the
// metadata into *info when not null (fields the stream lacks keep their defaults). Throws
// (std::exception) for a stream OpenVDB cannot parse.
std::map<std::string, LevelSet> readLevelSets(std::istream& in, LevelSetFileInfo* info);

// Version string of the OpenVDB library in use (for run.json).
std::string openvdbVersion();

}  // namespace kurage::render
