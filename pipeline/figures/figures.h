// The paper's figures (Hirato & Kawaguchi 2009; SPEC §5) from its three experiments, each in the
// paper's layout, written into one folder by `kurage figures DIR`:
//   fig2_membrane.png  SPEC §4.1: fluid poured onto the pinned membrane, one column per moment;
//                      rows: the telescopic model (membrane.json), its cross-section (the same
//                      frame with the half in front of the sheet's middle clipped away), and the
//                      conventional mass-spring model (membrane_conventional.json) leaking
//   fig3_box.png       SPEC §4.2: box.json's float, contract-and-sink, release-and-rise, swell and
//                      float again, above the applied force per spring against time (fig3_force.*)
//   fig5_jellyfish.png SPEC §4.3: frames over one pulse cycle while the right faucet pours, above
//                      the ring muscle's force per spring over that cycle (fig5_force.*)
// Every still carries its moment ("t = 4 s") in its top left corner, in Fig. 3 and 5 after its
// number, the number of its marker on the plot; Fig. 2's rows are named at their left
// (render/text.h draws the labels). The plots are also SVG, PDF and gnuplot scripts
// (pipeline/io/plot.h); figures.json records each figure's scene, moments, camera and wall time,
// and the stills' integrator and samples.
//
// Each experiment is simulated once, in process, only as far as its figure's last moment, and
// sampled at the scene's own frame rate (output.fps: the frames are those `kurage run` writes at
// final quality); the muscle force plotted is the one applied in the step before each sample
// (a depth reflex scales the pulse). Stills are surfaced and rendered as the stages do. Fig. 2's
// view is the scenes' raised 2 m (the fluid piled over the rim stays in the frame); Fig. 3's
// looks at the tank's front from below the scene's, so that the box is seen once, at its depth,
// not also through the water's surface; Fig. 5's is placed from the simulated bell and the
// pouring nozzle, so it frames the bell and the jet whatever the scene's own camera.
//
// Quality: tiny (seconds: the first tenths of a second at thumbnail size, for tests), preview
// (the scenes' preview_quality, minutes on 2 cores), final (the scenes as written, for print).
#pragma once

#include "pipeline/scene.h"
#include "render/image.h"

#include <Eigen/Core>

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace kurage::pipeline {

enum class FigureQuality { Tiny, Preview, Final };

// What a quality level sets for every figure's stills. Every level renders with the whitted
// integrator: noise-free, its checkers filtered over each pixel's footprint (render/renderer.h);
// the path tracer at the samples a figure can afford leaves grain on the translucent bodies and
// the far floor (docs/notebook/rendering.md, "The paper's figures").
struct FigureLevel {
  Quality scene;                      // the scenes' own quality (preview_quality or as written)
  render::IntegratorType integrator;  // replaces the scenes' own; the denoiser is off with whitted
  Eigen::Vector2i membrane, box, jellyfish;  // still sizes, px: Fig. 2, 3 and 5
  int samples;    // per pixel
  int maxDepth;   // 0: the scene's
  int gap;        // px between panels
  int textScale;  // image px per font px of the labels
};
FigureLevel figureLevel(FigureQuality quality);

// "tiny", "preview", "final"; parseFigureQuality throws std::invalid_argument for anything else.
const char* figureQualityName(FigureQuality quality);
FigureQuality parseFigureQuality(const std::string& name);

struct FigureOptions {
  std::filesystem::path scenesDir = "scenes";  // membrane.json, membrane_conventional.json, box.json, jellyfish.json
  std::filesystem::path outDir;                // created if missing
  FigureQuality quality = FigureQuality::Preview;
  std::vector<std::string> only;               // figure names ("fig2", "fig3", "fig5"); empty: all
  std::function<void(const std::string&)> log;  // one line per step, or nothing
};

// The figures' names, in the paper's order.
const std::vector<std::string>& figureNames();

// Writes the figures into options.outDir and returns the files written (figures first, then the
// plots' PNG, SVG, PDF and scripts, then figures.json). Throws std::runtime_error naming the
// file for a missing scene, gnuplot missing or failing, or an unwritable folder; SceneError for
// an invalid scene.
std::vector<std::filesystem::path> writeFigures(const FigureOptions& options);

// Images side by side (top-aligned) or one above another (centred), `gap` pixels of `background`
// between them and around narrower or shorter ones.
render::Image besideEachOther(const std::vector<render::Image>& images, int gap,
                              const Eigen::Vector4f& background = Eigen::Vector4f::Ones());
render::Image aboveEachOther(const std::vector<render::Image>& images, int gap,
                             const Eigen::Vector4f& background = Eigen::Vector4f::Ones());

// A pinhole camera's position looking along +y at the middle of the box [lo, hi] (x across,
// z up), far enough back that the box fills the frame of the given aspect (width / height) and
// vertical field of view, with `margin` of its size spare on each side.
struct FramedView {
  Eigen::Vector3f position, lookAt;
};
FramedView frameFromFront(const Eigen::Vector3f& lo, const Eigen::Vector3f& hi, float aspect, float fovDegrees,
                          float margin = 0.08f);

}  // namespace kurage::pipeline
