// Preview: particles drawn as shaded spheres with OpenGL, headless, through OSMesa (Mesa's
// off-screen GL on the llvmpipe software rasteriser, OpenGL 4.5 core profile). For a quick look
// at a simulation without surfacing; far faster than the ray tracer, and far simpler: no
// shadows, no ground, no reflections.
//
// Each sphere is a ray-cast impostor: one camera-facing quad per sphere (instanced) that covers
// its silhouette exactly under perspective; the fragment shader intersects the view ray with the
// sphere, discards misses and writes the true depth, so spheres intersect each other correctly.
// Shading is Lambert under one directional light plus a uniform ambient term, over a flat
// background colour. The camera is the tracer's (render/camera.h) used as a pinhole: its lens
// (aperture, focus) is ignored. Row 0 is at the top.
//
// Units: world space, metres. Colours are linear RGB in [0, 1]; the returned Image holds linear
// values (decoded from the 8-bit sRGB framebuffer, so writePng reproduces its bytes exactly).
// Rendering is deterministic: the same input gives the same pixels.
//
// It knows nothing of SPH: it takes positions, radii and colours. Not thread-safe: one
// PreviewRenderer per thread (OSMesa contexts are bound to the calling thread).
#pragma once

#include "render/camera.h"
#include "render/image.h"

#include <Eigen/Core>

#include <memory>
#include <string>
#include <vector>

namespace kurage::render {

struct PreviewSpheres {
  std::vector<Eigen::Vector3f> centres;  // world, metres
  std::vector<float> radii;              // metres, > 0 (one per centre)
  std::vector<Eigen::Vector3f> colours;  // linear RGB albedo in [0, 1] (one per centre)
};

struct PreviewSettings {
  int width = 640;
  int height = 360;
  Eigen::Vector3f background{0.85f, 0.9f, 0.95f};  // linear RGB
  Eigen::Vector3f lightDirection{-0.4f, -0.3f, -1.0f};  // direction the light travels (need not be unit)
  Eigen::Vector3f lightIrradiance{0.75f, 0.75f, 0.75f};  // on a surface facing the light (albedo = 1)
  float ambient = 0.3f;  // fraction of the albedo lit regardless of the light direction
};

// Owns an OSMesa context and its GL objects; reuse it for every frame of a sequence.
class PreviewRenderer {
public:
  // Throws std::runtime_error when OSMesa cannot create an OpenGL 4.5 core context.
  PreviewRenderer();
  ~PreviewRenderer();
  PreviewRenderer(const PreviewRenderer&) = delete;
  PreviewRenderer& operator=(const PreviewRenderer&) = delete;

  // Renders one frame. Throws std::invalid_argument for mismatched array lengths, a
  // non-positive image size or a degenerate camera, std::runtime_error for GL errors.
  Image render(const PreviewSpheres& spheres, const Camera& camera, const PreviewSettings& settings);

  // "Mesa 22.3.6 (llvmpipe ...)": GL_VERSION and GL_RENDERER of the context.
  std::string glVersion() const;

  struct Impl;

private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace kurage::render
