// Smaller blobs for airborne water (a jet, spray): which particles of a fluid get a metaball
// radius below the surface's R (surfacing.h, buildMetaballLevelSet with radius scales), so that a
// falling stream a few particles across reads as a stream instead of a blob of radius ~R.
//
// A particle is airborne by two measures, each a linear ramp clamped to [0, 1]:
//   fast   = (|v| - speedMin) / (speedFull - speedMin)
//   sparse = (fillMin - fill) / (fillMin - fillFull),  fill = n / ((4/3) pi R^3 / spacing^3)
// with n the particles within R of it (itself included): fill is about 1 in the bulk, 1/2 at a
// flat free surface, 1/4 along a wall's edge and less in a stream much thinner than R. Its weight
// is w = fast * sparse and its radius scale 1 - w (1 - radius / R): slow water (the still surface,
// the walls' edges) and dense water (the pool under a landing jet) keep exactly R (scale 1), so
// their surface is bit for bit the one without this rule. Both ramps are continuous, so a
// particle's blob shrinks and grows smoothly from frame to frame.
//
// Limits: fill counts fluid particles only, so a fast particle next to a wall or a body counts as
// sparser than it is. A splash faster than speedMin with few neighbours is shrunk like a jet.
#pragma once

#include <Eigen/Core>

#include <vector>

namespace kurage::render {

struct AirborneParams {
  bool enabled = false;
  float radius = 0.7f;     // m, blob radius of a fully airborne particle (w = 1); <= R
  float speedMin = 2.5f;   // m/s: slower particles are not airborne
  float speedFull = 4.0f;  // m/s: faster ones are fully fast (> speedMin)
  float fillFull = 0.3f;   // sparser particles are fully sparse
  float fillMin = 0.45f;   // denser ones are not airborne (> fillFull)
};

// One radius scale in (0, 1] per particle (see above); all 1 when !params.enabled. `radius` is R
// and `spacing` the fluid's particle spacing (metres, > 0); velocities in m/s, one per position.
// Throws std::invalid_argument for mismatched sizes, or (when enabled) parameters out of range.
std::vector<float> airborneRadiusScales(const std::vector<Eigen::Vector3f>& positions,
                                        const std::vector<Eigen::Vector3f>& velocities, float radius, float spacing,
                                        const AirborneParams& params);

}  // namespace kurage::render
