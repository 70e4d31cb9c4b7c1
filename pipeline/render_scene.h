// From a scene's "render" section to the renderer's own description (render/scene.h): camera at
// a time (keyframes), sun, area lights, environment (the image decoded here), ground, tank walls,
// faucets, clip plane, chains as tubes, and particles as coloured spheres for explanatory stills.
#pragma once

#include "pipeline/io/particle_cache.h"
#include "pipeline/scene.h"
#include "render/renderer.h"

#include <map>
#include <string>
#include <vector>

namespace kurage::pipeline {

// Everything but the geometry. Throws std::runtime_error naming the file if an environment image
// cannot be read.
render::RenderScene makeRenderScene(const Scene& scene, double time);

// Object ids in the render's layers (render/frame_layers.h, the EXR's object_id): 0 sky,
// 1 ground, 2 area lights, 3 the tank, then 4 + kind for the fluid (kind 0) and each body (kind k,
// kurage:kinds' order). objectNames(scene)[id] names each.
inline constexpr uint32_t kObjectTank = render::kObjectFirst;
inline uint32_t objectIdOfKind(int kind) { return render::kObjectFirst + 1 + uint32_t(kind); }
std::vector<std::string> objectNames(const Scene& scene);

// The tank walls (render.tank) seen from `eye`: the container's side walls whose inner face
// the eye sees, from container.min.z up to the tank height.
render::TriangleMesh tankMesh(const Scene& scene, const Eigen::Vector3f& eye);

// The emitters drawn as faucets (render.faucets, in makeRenderScene when enabled): per emitter a
// tube of radius kFaucetRadiusScale x the nozzle's radius whose rounded end touches the nozzle's
// disc, straight back along the emitter's direction until it is two radii above the tank's rim
// (render.tank.height, else container.max.z; at least two radii long), then straight up for
// kFaucetRise (a B-spline, so the bend is rounded). Material render.faucets.material; object id
// the tank's. A pipe whose way back leaves the tank below the rim passes through its wall.
inline constexpr float kFaucetRadiusScale = 1.2f;
inline constexpr float kFaucetRise = 8.0f;  // metres
render::CurveSet faucetTubes(const Scene& scene);

// The particles of a frame as spheres coloured by render.particles.color_by (kind, speed or
// rest-density factor, the latter read as 1 where the cache has none).
render::SphereSet particleSpheres(const Scene& scene, const ParticleFrame& frame);

// Whether the scene has chain bodies (drawn as tubes from the particle caches).
bool hasChains(const Scene& scene);

// A chain body's particles in chain order: indices into the frame, from the particle it hangs by
// to its tip (by id: sim::BodySystem numbers a chain's particles in that order). Chains with no
// particle in the frame are left out.
struct ChainOrder {
  int kind = 0;
  std::vector<size_t> indices;
};
std::vector<ChainOrder> chainOrder(const Scene& scene, const ParticleFrame& frame);

// One tube per chain body with at least two particles (render::Tube: a uniform cubic B-spline
// with the particles as control points, passing through the first and last), in chain order, the
// radius tapering linearly with the particle index from render.chain_radius.root at the chain's
// first particle to .tip at its last; material render.chain_material. A particle at the same
// place as the one before it is left out (a zero-length segment has no direction).
render::CurveSet chainTubes(const Scene& scene, const ParticleFrame& frame);

// The colour ramp used for speed and rest-density factor: t in [0,1] from dark blue through
// teal and green to yellow (clamped outside).
Eigen::Vector3f colourRamp(float t);

}  // namespace kurage::pipeline
