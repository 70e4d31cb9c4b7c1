// Lights: a directional sun with an angular size, one-sided rectangular area lights, and the
// environment (sky gradient, uniform, or a latitude-longitude image) seen by rays that leave
// the scene. Radiometric quantities are linear RGB; radiance is W/(m^2 sr) in arbitrary units,
// irradiance W/m^2 in the same units.
//
// The sun and the area lights are sampled by next-event estimation (integrators/); the
// environment too, by its luminance (EnvironmentSampler), unless RenderSettings turns that off.
#pragma once

#include "render/image.h"

#include <Eigen/Core>

#include <memory>
#include <vector>

namespace kurage::render {

// The sun: a disk of uniform radiance subtending `angularDiameterDegrees`, specified by the
// irradiance it gives a surface facing it. 0 degrees gives a point (delta) light with hard
// shadows; the real sun is 0.53 degrees.
struct SunLight {
  Eigen::Vector3f direction{-0.4f, -0.3f, -1.0f};  // direction the light travels (need not be unit)
  Eigen::Vector3f irradiance{2.6f, 2.5f, 2.3f};    // on a surface facing the sun
  float angularDiameterDegrees = 0.53f;
};

// A rectangle corner + s edgeU + t edgeV (s, t in [0,1]) emitting `radiance` from the side that
// edgeU x edgeV points to; the back is black. Seen directly and in mirrors; it casts no shadow.
struct RectLight {
  Eigen::Vector3f corner{0, 0, 10};
  Eigen::Vector3f edgeU{2, 0, 0};
  Eigen::Vector3f edgeV{0, 2, 0};
  Eigen::Vector3f radiance{10, 10, 10};
};

enum class EnvironmentType { Gradient, Uniform, Image };

// Radiance arriving from directions that hit nothing.
//   gradient  horizon colour at and below the horizon, blending linearly in sin(elevation) to
//             the zenith colour straight up
//   uniform   `zenith` from every direction (the furnace)
//   image     an equirectangular (latitude-longitude) picture, decoded to linear values, times
//             `intensity`; its centre column looks along +x rotated by `rotationDegrees` about up
struct Environment {
  EnvironmentType type = EnvironmentType::Gradient;
  Eigen::Vector3f zenith{0.35f, 0.55f, 0.9f};
  Eigen::Vector3f horizon{0.85f, 0.9f, 0.95f};
  Eigen::Vector3f up{0, 0, 1};
  std::shared_ptr<const Image> image;  // for EnvironmentType::Image
  float intensity = 1.0f;
  float rotationDegrees = 0.0f;
};

// Radiance of the environment in unit direction `direction`.
Eigen::Vector3f environmentRadiance(const Environment& environment, const Eigen::Vector3f& direction);

// Importance sampling of the environment in proportion to its luminance: a piecewise-constant
// 2-D distribution over the equirectangular square (u, v) in [0,1)^2 (pbrt's Distribution2D,
// Pharr, Jakob & Humphreys, 4th ed., sec. A.5 and 12.6), one cell per image pixel for an image
// sky (so a cell's value is exactly what environmentRadiance returns inside it) and 64 x 32
// cells for the analytic skies (their luminance at the cell centre). A cell's weight is its
// luminance times sin(theta) at its centre, theta the angle from `up`; the solid-angle pdf of a
// direction is p(u, v) / (2 pi^2 sin(theta)).
//
// With `below` (a unit ground normal), cells that lie wholly below that plane's horizon get
// weight 0: the infinite ground hides them from every point above it. Directions of weight 0
// are left to BSDF sampling, which the MIS weight (power heuristic) then counts in full, so the
// estimate stays unbiased. Sampling allocates nothing. Building costs one radiance lookup and
// 12 bytes per cell (a 2048 x 1024 sky image: about 25 MB); a Renderer builds it once and keeps
// it while the environment and the ground's normal stay the same (renderer.h). Limit: an image
// sky is not downsampled, so its cells are its pixels however large it is.
class EnvironmentSampler {
public:
  EnvironmentSampler() = default;  // samples nothing (pdf 0 everywhere)
  EnvironmentSampler(const Environment& environment, const Eigen::Vector3f* below);
  bool empty() const { return total_ <= 0.0; }
  // A direction for two uniform numbers in [0,1); pdf (per solid angle) 0 when nothing was drawn.
  Eigen::Vector3f sample(float u1, float u2, float& pdf) const;
  // The solid-angle pdf with which sample() returns unit `direction`.
  float pdf(const Eigen::Vector3f& direction) const;

private:
  Eigen::Vector3f directionAt(float u, float v) const;
  // std::upper_bound(cdf + 1, cdf + count + 1, target) - cdf - 1 (the last i with cdf[i] <= target),
  // started from the guide table's entry for target / cdf[count] and scanned forward; the same
  // index as the binary search (which it falls back to if the guide overshoots), in about one step.
  static int find(const double* cdf, int count, const int* guide, double target);
  static void buildGuide(const double* cdf, int count, int* guide);
  int width_ = 0, height_ = 0;
  std::vector<float> weights_;     // width x height, row-major (v rows)
  std::vector<double> rowCdf_;     // height x (width + 1): cumulative weights within each row
  std::vector<double> marginal_;   // height + 1: cumulative row sums
  std::vector<int> rowGuide_;      // height x width: per row, the column search's guide table
  std::vector<int> marginalGuide_; // height: the row search's guide table
  double total_ = 0.0;
  Eigen::Vector3f up_{0, 0, 1}, tangent_{1, 0, 0}, bitangent_{0, 1, 0};
  float rotation_ = 0.0f;  // radians
};

}  // namespace kurage::render
