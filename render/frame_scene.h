// One frame's scene as the integrators see it: the closest hit among the Embree geometry
// (embree_scene.h), the analytic ground and the area lights; the transmittance of shadow rays; and
// the lights' derived quantities (the sun's direction, cone and radiance, the environment's
// sampler). Read-only while the frame renders, so any number of threads may query it.
//
// The sun of angular radius r (lights.h) is a cone of directions about toSun with
// cos r = sunCosMax and solid angle 2 pi (1 - cos r); its radiance is irradiance / solid angle
// (0 for a point sun, r = 0, which only shadow rays find).
//
// Shadow rays (transmittance) with transmissive shadows pass dielectric surfaces straight: each
// crossing lets (1 - F) through, F taken at that angle from the air's side (so no total internal
// reflection: a wave facet steeper than the critical angle does not cast a black shadow, which
// the refracted light of its neighbours would fill), the medium absorbs exp(-absorption * length),
// and the radiance is divided by ior^2 for every medium the ray leaves and multiplied by it for
// every one it enters. A shading point under water thus receives 1/ior^2 of what the unbent ray
// carries: the sky seen from under a flat surface is squeezed into a cone whose projected solid
// angle is 1/ior^2 of the hemisphere's, and a beam (the sun, a small light) crosses the same
// horizontal area, while the integrators do not scale radiance at refractions (materials.cpp), so
// the camera's path out of the water does not undo it. For a flat surface over a parallel floor
// the unbent ray then gives exactly the irradiance of the refracted paths (conservation of
// etendue, n^2 cos dw invariant); a ray through a parallel slab from air to air keeps (1 - F)^2,
// the slab's exact single-pass transmission. The surfaces on the segment come from one traversal
// (EmbreeScene::crossings), sorted by distance, the absorbed lengths measured between consecutive
// crossings; an opaque surface, or more than 16 crossings, give 0.
// Without transmissive shadows any surface blocks.
#pragma once

#include "render/embree_scene.h"
#include "render/hit.h"
#include "render/lights.h"
#include "render/scene.h"

#include <Eigen/Core>

#include <algorithm>

namespace kurage::render {

struct FrameScene {
  // `geometry` built from `scene` (EmbreeScene::update); `environment` empty unless the
  // environment is sampled as a light. All three must outlive this.
  FrameScene(const RenderScene& scene, const EmbreeScene& geometry, const EnvironmentSampler& environment,
             bool transmissiveShadows);

  // Closest hit among the Embree geometry, the ground and the area lights (kind None: the ray
  // leaves the scene).
  Hit intersect(const Eigen::Vector3f& origin, const Eigen::Vector3f& direction, RayCounters& counters) const;
  // Fraction of light that reaches `origin` along unit `direction` from distance tfar (see above).
  Eigen::Vector3f transmittance(const Eigen::Vector3f& origin, const Eigen::Vector3f& direction, float tfar,
                                RayCounters& counters) const;
  // Whether the infinite ground stands in the way of the ray (shadow rays ignore it otherwise: it
  // casts no shadows, but the sky below its horizon must not light anything above it). `origin`
  // must be off the ground (leave()): a point computed on it lies a rounding error above or below.
  bool groundBlocks(const Eigen::Vector3f& origin, const Eigen::Vector3f& direction) const;
  // The hit's albedo box-filtered over the footprint of a ray cone (Amanatides 1984; Akenine-Moller
  // et al. 2021, "Improved shader and texture level of detail using ray cones", JCGT 10(1)) of
  // width `width` (metres, at the hit) along unit `direction`: on the surface an ellipse of axes
  // width across the ray and width / |cos| along it (cos = direction . ng, at least 1e-4); each
  // checker axis is averaged over a box of the full width sqrt(a1_i^2 + a2_i^2) (a1, a2 the
  // ellipse's axes: the box of the same variance). The ground's checker in its (u, v) axes, a
  // material's 3-D checker in x, y, z (materials.h); hit.albedo where there is no checker or the
  // width is 0.
  Eigen::Vector3f filteredAlbedo(const Hit& hit, const Eigen::Vector3f& direction, float width) const;
  // The hit's albedo with a checker (the ground's or a material's) replaced by the mean of its
  // two colours, the limit of filteredAlbedo over a wide footprint; hit.albedo otherwise.
  Eigen::Vector3f meanAlbedo(const Hit& hit) const;
  // Where a ray leaving the hit in direction wi starts: the point moved along ng to wi's side by
  // offset(hit).
  Eigen::Vector3f leave(const Hit& hit, const Eigen::Vector3f& wi) const {
    const float d = offset(hit);
    return hit.point + (wi.dot(hit.ng) > 0.0f ? d : -d) * hit.ng;
  }
  // The distance a leaving ray's origin is moved off the surface: epsilon, or, where larger, a
  // bound on the rounding error of the point computed as o + t d (each coordinate off by at most a
  // few ulps of |o| + t <= |p| + 2t, as in pbrt-v4's error bounds, Pharr et al. 2023, sec. 6.8), so
  // that a far point of the ground or of a large surface does not find itself again.
  float offset(const Hit& hit) const {
    return std::max(epsilon, kOffsetUlps * (hit.point.cwiseAbs().maxCoeff() + 2.0f * hit.t));
  }
  static constexpr float kOffsetUlps = 16.0f * 0x1p-24f;  // 16 ulps of float's unit roundoff

  const RenderScene& input;
  const EmbreeScene& geometry;
  const EnvironmentSampler& environment;
  bool transmissiveShadows;
  float epsilon;                 // ray offset against self-intersection, metres
  Eigen::Vector3f toSun;         // unit, towards the sun
  float sunCosMax = 1.0f;        // cos of the sun's angular radius
  Eigen::Vector3f sunRadiance;   // irradiance / solid angle (0 for a point sun)
  bool sunOn = false;
  Eigen::Vector3f groundNormal = Eigen::Vector3f::UnitZ();  // unit
  Eigen::Vector3f groundU, groundV;                         // unit, spanning the ground plane (checker axes)
};

}  // namespace kurage::render
