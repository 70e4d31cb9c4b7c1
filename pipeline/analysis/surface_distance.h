// How far a metaball level set lies from the exact metaball surface it approximates
// (render/surfacing.h): the exact field, summed over the particles, and the distance between the
// two surfaces along rays from the particles' centroid. Metres.
#pragma once

#include "render/surfacing.h"

#include <Eigen/Core>

#include <cstdint>
#include <vector>

namespace kurage::pipeline {

// The exact metaball field f(x) = sum s (1 - (|x - x_i| / R)^2)^2 of render/surfacing.h,
// summed over all particles within R (a bucket grid of cell R).
class MetaballField {
public:
  MetaballField(std::vector<Eigen::Vector3f> points, const render::MetaballParams& params);
  double operator()(const Eigen::Vector3d& x) const;
  const Eigen::Vector3d& centroid() const { return centroid_; }
  double reach() const { return reach_; }  // max distance of a particle from the centroid, plus R

private:
  std::vector<Eigen::Vector3f> points_;
  render::MetaballParams params_;
  Eigen::Vector3d centroid_ = Eigen::Vector3d::Zero();
  double reach_ = 0.0;
  Eigen::Vector3i cells_ = Eigen::Vector3i::Zero();
  Eigen::Vector3d lower_ = Eigen::Vector3d::Zero();
  std::vector<uint32_t> cellStart_, cellPoints_;
};

// Distance of a level set's zero crossing from the exact surface f = T, along `rays` rays from
// the particles' centroid in directions spread evenly over the sphere (a Fibonacci lattice):
// on each ray, the outermost crossing of each (marched inwards from outside in steps of a tenth
// of min(R, voxel), then bisected to 1e-6 of the voxel). The particle arrangement must be
// star-shaped about its centroid for the distance along a ray to be the distance to the surface
// (a lattice block or ball is); rays that miss one of the surfaces count as failures.
struct SurfaceDistance {
  double mean = 0.0;  // m
  double max = 0.0;   // m
  double rms = 0.0;   // m
  int rays = 0;       // rays that found both crossings
  int misses = 0;     // rays where only one surface was found
};
SurfaceDistance surfaceDistance(const render::LevelSet& levelSet, const MetaballField& field,
                                const render::MetaballParams& params, int rays);

}  // namespace kurage::pipeline
