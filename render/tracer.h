// Headless Embree 3 path tracer.
//
// Renders triangle meshes (the level set surfaces), sphere sets (particles shown as spheres) and
// tubes along curves (the jellyfish's oral arms) with materials (materials.h) over an analytic
// infinite checker ground, lit by a sun, area lights and the environment (lights.h), seen through
// a perspective camera (camera.h).
//
// The default integrator is a unidirectional path tracer with next-event estimation for the sun,
// the area lights and the environment at every non-specular vertex, Russian roulette once a
// path's throughput falls below 1 (from the third bounce on), and a hard maximum number of
// scattering events. The sun and the area lights are added on hit only after a specular bounce
// or at the camera; the environment, found by a BSDF-sampled path, is weighted against its
// shadow-ray estimate by Veach's power heuristic (RenderSettings::environmentSampling), so no
// path is counted twice. By default shadow rays pass through dielectrics
// (RenderSettings::transmissiveShadows), and the camera ray's first Fresnel interface is split
// into both branches (RenderSettings::fresnelSplitting).
// Beer-Lambert absorption attenuates paths inside dielectric and translucent objects.
//
// Every random number is a pure function of (pixel, sample, dimension, seed) (sampling.h), so
// the image depends only on the scene, the settings and the seed: not on the thread count or the
// order in which the 16x16 tiles are rendered.
//
// Units are metres in world space. The ground is the plane through `point` with normal `normal`
// (analytic, truly infinite, receives shadows but casts none). A clip plane removes the meshes,
// spheres and tubes (not the ground) on the side its normal points to, for cross-section views.
#pragma once

#include "render/camera.h"
#include "render/denoise.h"
#include "render/frame_layers.h"
#include "render/image.h"
#include "render/lights.h"
#include "render/materials.h"
#include "render/mesh.h"

#include <Eigen/Core>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace kurage::render {

struct Ground {
  bool enabled = true;
  Eigen::Vector3f point{0, 0, 0};
  Eigen::Vector3f normal{0, 0, 1};
  Eigen::Vector3f albedoA{0.65f, 0.65f, 0.62f};  // diffuse checker colours
  Eigen::Vector3f albedoB{0.3f, 0.3f, 0.28f};
  float checkerSize = 1.0f;  // metres; <= 0 gives a plain albedoA ground
};

struct ClipPlane {
  bool enabled = false;
  Eigen::Vector3f point{0, 0, 0};
  Eigen::Vector3f normal{0, 1, 0};  // geometry where (x - point) . normal > 0 is removed
};

struct SceneObject {
  const TriangleMesh* mesh = nullptr;  // not owned; must outlive renderFrame()
  Material material;
  uint32_t objectId = kObjectFirst;  // FrameLayers::objectId where it is seen first
};

// Spheres of one radius; each may have its own colour (replacing material.albedo).
struct SphereSet {
  std::vector<Eigen::Vector3f> centres;  // metres
  std::vector<Eigen::Vector3f> colours;  // empty, or one per centre
  float radius = 0.5f;                   // metres
  Material material;
  uint32_t objectId = kObjectFirst;
};

// Closed tubes of varying radius along uniform cubic B-splines, traced directly as Embree's
// round B-spline curves (RTC_GEOMETRY_TYPE_ROUND_BSPLINE_CURVE: a circle of the interpolated
// radius swept along the curve, perpendicular to it), never meshed.
//
// A tube's `points` are the B-spline's control points and `radii` its radius at each (metres,
// > 0). A uniform cubic B-spline passes through none of its control points, so the tracer adds
// one more at each end, mirrored through the end point (2 p0 - p1, and likewise the radius):
// the curve then starts exactly at the first point with radius radii.front() and tangent p1 - p0,
// and ends exactly at the last one; n >= 2 points give n - 1 curve segments (a single point
// gives nothing). Embree's tube is open at its ends; the tracer closes each end with the half of
// a sphere of the end radius that lies outside the tube, so the tube is a closed surface and
// dielectric and translucent materials work inside it. The interpolated radius stays > 0 (all
// radii > 0). Limits (Embree's): the radius must stay below the curve's radius of curvature, and
// consecutive points must differ; otherwise the surface shows artefacts.
struct Tube {
  std::vector<Eigen::Vector3f> points;  // metres
  std::vector<float> radii;             // metres, one per point
  uint32_t objectId = 0;                // FrameLayers::objectId; 0: the set's
};

struct CurveSet {
  std::vector<Tube> tubes;
  Material material;
  uint32_t objectId = kObjectFirst;
};

struct RenderScene {
  std::vector<SceneObject> meshes;
  std::vector<std::shared_ptr<const TriangleMesh>> ownedMeshes;  // keeps meshes built with the scene alive
  std::vector<SphereSet> spheres;
  std::vector<CurveSet> curves;
  Camera camera;
  SunLight sun;
  std::vector<RectLight> rectLights;
  Environment environment;
  Ground ground;
  ClipPlane clip;
};

// How radiance is estimated (RenderSettings::integrator).
//   path     the unbiased path tracer described at the top of this file.
//   whitted  deterministic ray tracing in the manner of Whitted (1980) and POV-Ray: at dielectric
//            surfaces both the Fresnel-reflected and the refracted ray are followed (a tree, cut
//            at maxDepth and where a branch's weight falls below 1e-3), mirrors reflect, and
//            diffuse surfaces take only direct light: the sun along its centre direction (hard
//            shadows), each area light at the centres of a lightSamples x lightSamples grid, and
//            the sky along `skyDirections` fixed cosine-distributed directions about the normal
//            (each with its shadow ray), which differ from sample to sample of a pixel: sample s
//            takes points s, s + S, ... of one Hammersley set of skyDirections x S points (S =
//            samplesPerPixel), the same at every pixel, so the pixel averages skyDirections x S
//            directions and the sky's shadows are not skyDirections hard copies. Shadow rays
//            follow RenderSettings::transmissiveShadows. Translucent bodies are shaded as diffuse
//            with albedo tint^2 (1 - F) (light scattered in and out once) plus the Fresnel
//            reflection. No indirect diffuse light, no caustics. Pixels are anti-aliased with
//            samplesPerPixel sub-pixel positions of a fixed (0,2)-sequence: the image depends on
//            neither the seed nor the thread count, and has no noise.
enum class Integrator { Path, Whitted };

struct WhittedSettings {
  int skyDirections = 16;  // shadow rays towards the sky per diffuse point, >= 1
  int lightSamples = 2;    // grid points per side on each area light, >= 1
};

// Adaptive sampling (path integrator): every pixel takes minSamples paths, then more in batches
// of minSamples until the standard error of its mean luminance falls below relativeError times
// max(mean, 0.05) (the floor keeps dark pixels from demanding endless samples) or maxSamples is
// reached. The error is estimated from the luminance's sample variance. samplesPerPixel is then
// ignored. Sub-pixel positions follow a (0,2)-sequence whose every prefix of 2^k is stratified.
struct AdaptiveSettings {
  bool enabled = false;
  float relativeError = 0.05f;  // > 0
  int minSamples = 8;           // >= 2
  int maxSamples = 256;         // >= minSamples
};

struct RenderSettings {
  int width = 640;
  int height = 360;
  int samplesPerPixel = 16;
  int maxDepth = 8;   // most scattering events on a path (1 = direct light only)
  int seed = 0;  // >= 0; another seed gives another, equally valid, noise pattern
  // Shadow rays pass through dielectric surfaces (Fresnel transmission, absorption, no bending),
  // and light sources are then counted on hit only after pure specular chains from the camera:
  // the light under water is far less noisy, at the price of caustics. false = exact transport
  // (caustics only from the sun's disk, noisy).
  bool transmissiveShadows = true;
  bool transparentBackground = false;  // alpha = fraction of camera rays that hit something;
                                       // the environment is then not seen directly
  // Next-event estimation for the environment (path integrator): at every diffuse or
  // translucent vertex one shadow ray towards a direction drawn by EnvironmentSampler (lights.h),
  // combined with the BSDF-sampled rays that escape to the sky by Veach's power heuristic. With
  // transmissive shadows the shadow ray passes water unbent, its radiance divided by ior^2 where
  // it leaves the water (Snell's window: exact for a flat surface over a parallel floor), and
  // escaping paths whose specular chain after the last diffuse vertex holds only refractions are
  // then not counted again. false: the sky is found only by escaping paths.
  bool environmentSampling = true;
  // Path integrator: where a camera ray first meets water or glass from outside, follow both the
  // Fresnel-reflected and the refracted ray (weights F, 1 - F) instead of choosing one at random;
  // removes the noise of that choice (the sky mirrored on the water) for one more path from there.
  bool fresnelSplitting = true;
  Integrator integrator = Integrator::Path;
  WhittedSettings whitted;
  AdaptiveSettings adaptive;
  // Path integrator: filter the frame with render/denoise.h, guided by the albedo and normal of
  // the first non-specular vertex of each camera path (gathered while tracing).
  DenoiseSettings denoise;
};

struct RenderStats {
  uint64_t primaryRays = 0;  // camera rays
  uint64_t totalRays = 0;    // every Embree query: camera, bounce and shadow rays
  uint64_t samples = 0;      // paths (or, whitted, sub-pixel trees) traced over the whole image
  double seconds = 0.0;      // wall time of renderFrame, scene build included
};

// Renders one frame (linear radiance, alpha). Throws std::invalid_argument for bad settings or
// scene data and std::runtime_error if Embree fails. `layers`, when given, receives what the
// camera ray through each pixel centre (lens centre) meets first (frame_layers.h); its
// objectNames are left as they were.
Image renderFrame(const RenderScene& scene, const RenderSettings& settings, RenderStats* stats = nullptr,
                  FrameLayers* layers = nullptr);

// Version string of the Embree library in use (for run.json).
std::string embreeVersion();

}  // namespace kurage::render
