// The union of spheres around particles as a narrow-band level set, by OpenVDB's own
// tools::ParticlesToLevelSet (Museth et al.): each particle's sphere of `radius` (world units,
// metres) is rasterised as a signed distance and the spheres are combined with CSG union.
// It is not a metaball surface (no blending between particles: a flat sheet of particles gives
// a bumpy surface); kurage uses it only as a speed reference in `kurage bench surface`.
//
// Positions are in world space, metres. The level set has the given voxel size and a narrow
// band of halfWidth voxels on each side (negative inside, background halfWidth * voxelSize).
// Spheres smaller than 1.5 voxels are dropped by OpenVDB (its documented limit); the result
// may depend on the thread count in the last bits (OpenVDB merges per-thread grids).
#pragma once

#include "render/surfacing.h"

#include <Eigen/Core>

#include <vector>

namespace kurage::render {

LevelSet buildParticleSpheresLevelSet(const std::vector<Eigen::Vector3f>& positions, float radius, float voxelSize,
                                      float halfWidth = 3.0f);

}  // namespace kurage::render
