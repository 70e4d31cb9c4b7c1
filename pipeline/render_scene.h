// From a scene's "render" section to the renderer's own description (render/tracer.h): camera at
// a time (keyframes), sun, area lights, environment (the image decoded here), ground, tank walls,
// clip plane, and particles as coloured spheres for explanatory stills.
#pragma once

#include "pipeline/particle_cache.h"
#include "pipeline/scene.h"
#include "render/tracer.h"

#include <map>
#include <string>

namespace kurage::pipeline {

// Everything but the geometry. Throws std::runtime_error naming the file if an environment image
// cannot be read.
render::RenderScene makeRenderScene(const Scene& scene, double time);

// The tank walls (render.tank) seen from `eye`: the container's side walls whose inner face
// the eye sees, from container.min.z up to the tank height.
render::TriangleMesh tankMesh(const Scene& scene, const Eigen::Vector3f& eye);

// The particles of a frame as spheres coloured by render.particles.color_by (kind, speed or
// rest-density factor, the latter read as 1 where the cache has none).
render::SphereSet particleSpheres(const Scene& scene, const ParticleFrame& frame);

// The colour ramp used for speed and rest-density factor: t in [0,1] from dark blue through
// teal and green to yellow (clamped outside).
Eigen::Vector3f colourRamp(float t);

}  // namespace kurage::pipeline
