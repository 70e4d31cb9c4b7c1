#include "pipeline/figures/figures.h"

#include "pipeline/analysis/body_track.h"
#include "pipeline/interrupt.h"
#include "pipeline/io/files.h"
#include "pipeline/io/image_file.h"
#include "pipeline/io/plot.h"
#include "pipeline/render_scene.h"
#include "pipeline/scene.h"
#include "pipeline/scene_params.h"
#include "pipeline/sim_frame.h"
#include "pipeline/stages.h"
#include "render/text.h"
#include "sim/simulation.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace kurage::pipeline {

namespace fs = std::filesystem;

FigureLevel figureLevel(FigureQuality q) {
  switch (q) {
    case FigureQuality::Tiny:
      return {Quality::Preview, render::IntegratorType::Whitted, {40, 60}, {64, 36}, {48, 64}, 1, 3, 2, 1};
    case FigureQuality::Preview:
      return {Quality::Preview, render::IntegratorType::Whitted, {200, 300}, {320, 180}, {270, 360}, 8, 0, 4, 2};
    case FigureQuality::Final:
      return {Quality::Final, render::IntegratorType::Whitted, {400, 600}, {640, 360}, {480, 640}, 16, 0, 8, 4};
  }
  return {};
}

namespace {

const Eigen::Vector3f kForceColour(0.69f, 0.19f, 0.38f);

void say(const FigureOptions& o, const std::string& line) {
  if (o.log) o.log(line);
}

std::string seconds(double t) {
  char text[32];
  std::snprintf(text, sizeof text, "%g s", t);
  return text;
}

// The labels on a panel: white on a translucent dark box, ringed in black, so they read on sky,
// water and floor alike.
render::TextStyle panelLabel(int scale) {
  return {scale, Eigen::Vector4f(1, 1, 1, 1), Eigen::Vector4f(0, 0, 0, 0.8f), Eigen::Vector4f(0, 0, 0, 0.45f)};
}

// "t = 4 s", to the hundredth of a second.
std::string timeLabel(double t) { return "t = " + seconds(std::round(t * 100.0) / 100.0); }

// A still with its number (matching its plot marker; 0: none) and then its moment in its top left
// corner (the top right is where Fig. 5's faucet pours).
render::Image labelled(render::Image panel, int number, double time, int scale) {
  int x = 3 * scale;
  if (number > 0) {
    const std::string n = std::to_string(number);
    render::drawText(panel, x, 3 * scale, n, panelLabel(scale));
    x += render::textWidth(n, scale) + 6 * scale;
  }
  render::drawText(panel, x, 3 * scale, timeLabel(time), panelLabel(scale));
  return panel;
}

// A row's name read bottom to top, centred in a white margin as tall as the row, to its left.
render::Image withRowLabel(const render::Image& row, const std::string& name, int scale, int gap) {
  render::Image across(row.height(), render::textHeight(scale) + 2 * scale, Eigen::Vector4f::Ones());
  render::drawText(across, (across.width() - render::textWidth(name, scale)) / 2, scale, name,
                   {scale, Eigen::Vector4f(0, 0, 0, 1), Eigen::Vector4f::Zero(), Eigen::Vector4f::Zero()});
  render::Image upward(across.height(), across.width());  // turned a quarter anticlockwise
  for (int y = 0; y < across.height(); ++y)
    for (int x = 0; x < across.width(); ++x) upward.at(y, across.width() - 1 - x) = across.at(x, y);
  return besideEachOther({upward, row}, gap);
}

fs::path sceneFile(const FigureOptions& o, const std::string& name) {
  const fs::path file = o.scenesDir / name;
  if (!fs::is_regular_file(file))
    throw std::runtime_error(file.string() + ": missing (the figures need the repository's scenes; --scenes DIR)");
  return file;
}

Scene loadFigureScene(const fs::path& file, const FigureLevel& level, const Eigen::Vector2i& size) {
  Scene scene = loadScene(file);
  applyQuality(scene, level.scene);
  render::RenderSettings& s = scene.render.settings;
  s.width = size.x();
  s.height = size.y();
  s.samplesPerPixel = level.samples;
  s.integrator = level.integrator;
  if (s.integrator == render::IntegratorType::Whitted) s.denoise.enabled = false;  // whitted has no noise to filter
  if (level.maxDepth > 0) s.maxDepth = std::min(s.maxDepth, level.maxDepth);
  checkSceneLimits(scene, file.string());
  return scene;
}

// One run of a scene sampled at `fps` up to the last moment: the first body's centre of mass and
// first muscle's applied force at every sample (as BodyTrack records them), and the particle
// frames at the moments (each moved to the nearest sample).
struct Run {
  std::vector<double> time, force;
  std::vector<Eigen::Vector3d> centre;
  std::vector<ParticleFrame> frames;
  std::vector<double> moments;  // the frames' times
};

Run simulate(const Scene& scene, std::vector<double> moments, double until, double fps) {
  Run run;
  for (double& t : moments) t = std::round(t * fps) / fps;
  until = std::max(until, moments.empty() ? 0.0 : moments.back());
  sim::Simulation simulation(scene.sim);
  simulation.setStopChecks(interruptPending);
  const int samples = int(std::ceil(until * fps - 1e-6));
  BodyTrack track(scene.sim, scene.name, samples + 1);
  track.start(simulation);
  const bool body = !scene.sim.bodies.empty(), muscle = body && !scene.sim.bodies[0].muscles.empty();
  size_t next = 0;
  for (int k = 0; k <= samples; ++k) {
    const double t = k / fps;
    if (k > 0) simulation.advanceTo(t);
    track.record(simulation);
    run.time.push_back(t);
    run.centre.push_back(body ? track.rows().back().centres[0] : Eigen::Vector3d::Zero());
    run.force.push_back(muscle ? track.rows().back().forces[0] : 0.0);
    while (next < moments.size() && std::abs(moments[next] - t) < 0.5 / fps) {
      run.frames.push_back(frameFromSimulation(scene, simulation, int(run.frames.size())));
      run.moments.push_back(t);
      ++next;
    }
  }
  return run;
}

render::Image renderStill(const Scene& scene, const ParticleFrame& frame, double time) {
  render::Renderer renderer;
  renderer.setStopCheck(interruptPending);
  std::vector<render::CurveSet> curves;
  if (hasChains(scene)) curves.push_back(chainTubes(scene, frame));  // chains are tubes, not surfaces
  render::Image image =
      renderSurfaces(scene, surfaceFrame(scene, frame, interruptPending), time, nullptr, curves, nullptr, &renderer);
  throwIfInterrupted();
  return image;
}

// The plots are as wide as the strip above them, and never narrower than their labels need; a
// strip wider than the preview's (about 1,600 px) scales the plot's text, lines and markers with
// it, so that they keep their size relative to the figure.
void sizePlot(Plot& plot, int stripWidth) {
  plot.scale = std::max(1.0, stripWidth / 1600.0);
  plot.width = std::max(stripWidth, 480);
  plot.height = std::clamp(stripWidth / 5, 180, int(420 * plot.scale));
}

// The force against time, with a numbered marker at each still's moment (1, 2, ... left to right).
Plot forcePlot(const Run& run, double t0, double t1, const std::string& xLabel, const std::string& yLabel,
               int stripWidth) {
  Plot plot;
  plot.x.label = xLabel;
  plot.y.label = yLabel;
  plot.x.min = 0.0;
  plot.x.max = t1 - t0;
  plot.legend = false;
  sizePlot(plot, stripWidth);
  PlotSeries force;
  force.colour = kForceColour;
  force.lineWidth = 3.0;
  for (size_t k = 0; k < run.time.size(); ++k)
    if (run.time[k] >= t0 - 1e-9 && run.time[k] <= t1 + 1e-9) {
      force.x.push_back(run.time[k] - t0);
      force.y.push_back(run.force[k]);
    }
  PlotSeries marks;
  marks.lines = false;
  marks.markers = true;
  marks.markerSize = 1.5;
  marks.colour = Eigen::Vector3f(0.1f, 0.1f, 0.1f);
  for (size_t f = 0; f < run.moments.size(); ++f) {
    const auto at = std::min_element(run.time.begin(), run.time.end(), [&](double a, double b) {
      return std::abs(a - run.moments[f]) < std::abs(b - run.moments[f]);
    });
    marks.x.push_back(run.moments[f] - t0);
    marks.y.push_back(run.force[size_t(at - run.time.begin())]);
    marks.pointLabels.push_back(std::to_string(f + 1));
  }
  plot.series = {force, marks};
  return plot;
}

// Draws the plot (PNG, SVG, PDF, script) and reads its PNG back for the composite.
render::Image drawPlot(const Plot& plot, const fs::path& png, std::vector<fs::path>& written) {
  writePlot(plot, png);
  if (!fs::exists(png))
    throw std::runtime_error(png.string() + ": not drawn (the figures' plots need gnuplot; .ci/install-deps installs it)");
  for (const char* ext : {".png", ".svg", ".pdf", ".gp"}) written.push_back(fs::path(png).replace_extension(ext));
  return render::readPng(png);
}

nlohmann::json cameraJson(const render::Camera& c) {
  return {{"position", {c.position.x(), c.position.y(), c.position.z()}},
          {"look_at", {c.lookAt.x(), c.lookAt.y(), c.lookAt.z()}},
          {"fov", c.verticalFovDegrees}};
}

// Fig. 2: columns are moments; rows the telescopic membrane, its cross-section, the conventional.
nlohmann::json figure2(const FigureOptions& o, const FigureLevel& level, std::vector<fs::path>& written) {
  const std::vector<double> moments = o.quality == FigureQuality::Tiny ? std::vector<double>{0.5}
                                                                         : std::vector<double>{4.0, 8.0, 12.0};
  const fs::path telescopicFile = sceneFile(o, "membrane.json"), conventionalFile = sceneFile(o, "membrane_conventional.json");
  Scene telescopic = loadFigureScene(telescopicFile, level, level.membrane);
  Scene conventional = loadFigureScene(conventionalFile, level, level.membrane);
  // The scenes' view raised 2 m, so that the fluid piled over the rim by 12 s stays in the frame.
  for (Scene* scene : {&telescopic, &conventional}) {
    scene->render.cameraKeys.clear();
    scene->render.camera.position.z() += 2.0f;
    scene->render.camera.lookAt.z() += 2.0f;
  }
  Scene section = telescopic;
  const sim::ContainerParams& box = telescopic.sim.container;
  section.render.clip = {true, {0.0f, 0.5f * (box.min.y() + box.max.y()), 0.0f}, {0.0f, -1.0f, 0.0f}};
  std::vector<render::Image> rows[3];
  for (int variant = 0; variant < 2; ++variant) {
    const Scene& scene = variant == 0 ? telescopic : conventional;
    const fs::path& file = variant == 0 ? telescopicFile : conventionalFile;
    say(o, "fig2: simulating " + file.string() + " to " + seconds(moments.back()));
    const Run run = simulate(scene, moments, moments.back(), loadScene(file).output.fps);
    for (size_t f = 0; f < run.frames.size(); ++f) {
      say(o, "fig2: rendering " + file.filename().string() + " at " + seconds(run.moments[f]));
      const double t = run.moments[f];
      rows[variant == 0 ? 0 : 2].push_back(labelled(renderStill(scene, run.frames[f], t), 0, t, level.textScale));
      if (variant == 0) rows[1].push_back(labelled(renderStill(section, run.frames[f], t), 0, t, level.textScale));
    }
  }
  const char* names[3] = {"telescopic", "cross-section", "conventional"};
  std::vector<render::Image> strips;
  for (int r = 0; r < 3; ++r)
    strips.push_back(withRowLabel(besideEachOther(rows[r], level.gap), names[r], level.textScale, level.gap));
  const fs::path file = o.outDir / "fig2_membrane.png";
  writePng(aboveEachOther(strips, level.gap), file);
  written.push_back(file);
  return {{"file", file.filename().string()},
          {"scenes", {telescopicFile.string(), conventionalFile.string()}},
          {"moments_s", moments},
          {"layout", "columns: the moments (each panel's time at its top left); rows, named at their left: the "
                     "telescopic membrane, its cross-section (the half in front of the tank's middle clipped away), "
                     "the conventional mass-spring membrane"},
          {"camera", cameraJson(telescopic.render.camera)}};
}

// Fig. 3: the box's frames left to right above the applied force against time.
nlohmann::json figure3(const FigureOptions& o, const FigureLevel& level, std::vector<fs::path>& written) {
  const bool tiny = o.quality == FigureQuality::Tiny;
  // Floating, contracted on the bottom, released and rising, swollen, floating again
  // (box.json's force: contract 7-14 s, expand 23-30 s).
  const std::vector<double> moments = tiny ? std::vector<double>{0.25, 0.5} : std::vector<double>{5.0, 13.0, 18.0, 29.0, 37.0};
  const double until = tiny ? 0.5 : 38.0;
  const fs::path file = sceneFile(o, "box.json");
  Scene scene = loadFigureScene(file, level, level.box);
  // In front of the tank, the eye 3/4 of its height up, looking at a third of its height: the
  // box is seen once, through the front wall at its depth (from the scene's higher view it is
  // seen twice, through the water's surface and through the front wall).
  const sim::ContainerParams& tank = scene.sim.container;
  const Eigen::Vector3f middle = 0.5f * (tank.min + tank.max), size = tank.max - tank.min;
  scene.render.cameraKeys.clear();
  scene.render.camera.position = {middle.x(), tank.min.y() - 1.43f * size.y(), tank.min.z() + 0.75f * size.z()};
  scene.render.camera.lookAt = {middle.x(), middle.y(), tank.min.z() + size.z() / 3.0f};
  scene.render.camera.up = Eigen::Vector3f::UnitZ();
  scene.render.camera.verticalFovDegrees = 30.0f;
  say(o, "fig3: simulating " + file.string() + " to " + seconds(until));
  const Run run = simulate(scene, moments, until, loadScene(file).output.fps);
  std::vector<render::Image> stills;
  for (size_t f = 0; f < run.frames.size(); ++f) {
    say(o, "fig3: rendering box.json at " + seconds(run.moments[f]));
    stills.push_back(labelled(renderStill(scene, run.frames[f], run.moments[f]), int(f) + 1, run.moments[f],
                              level.textScale));
  }
  const render::Image strip = besideEachOther(stills, level.gap);
  const render::Image plot =
      drawPlot(forcePlot(run, 0.0, until, "time (s)", "force per spring (N)", strip.width()), o.outDir / "fig3_force.png", written);
  const fs::path figure = o.outDir / "fig3_box.png";
  writePng(aboveEachOther({strip, plot}, level.gap), figure);
  written.insert(written.end() - 4, figure);
  return {{"file", figure.filename().string()},
          {"plot", "fig3_force.png"},
          {"scenes", {file.string()}},
          {"moments_s", run.moments},
          {"layout", "frames 1-" + std::to_string(run.moments.size()) +
                         " left to right above the applied force per spring against time (markers 1-" +
                         std::to_string(run.moments.size()) + ": the frames' moments)"},
          {"camera", cameraJson(scene.render.camera)}};
}

// Fig. 5: frames over one pulse cycle while a faucet pours, above the ring muscle's force.
nlohmann::json figure5(const FigureOptions& o, const FigureLevel& level, std::vector<fs::path>& written) {
  const bool tiny = o.quality == FigureQuality::Tiny;
  const fs::path file = sceneFile(o, "jellyfish.json");
  Scene scene = loadFigureScene(file, level, level.jellyfish);
  if (scene.sim.bodies.empty() || scene.sim.bodies[0].muscles.empty() ||
      scene.sim.bodies[0].muscles[0].force.type != sim::CurveType::Pulse)
    throw std::runtime_error(file.string() + ": Fig. 5 needs the first body's first muscle to be pulsed");
  const sim::ForceCurve& pulse = scene.sim.bodies[0].muscles[0].force;
  const std::vector<sim::EmitterParams>& faucets = scene.sim.emitters;
  // The first whole cycle starting at least 2 s into a pour (the jet has reached the water).
  double t0 = pulse.start, period = pulse.period;
  if (!faucets.empty()) {
    const double from = faucets[0].start + 2.0;
    t0 = pulse.start + std::ceil(std::max(0.0, from - pulse.start) / period - 1e-9) * period;
  }
  if (tiny) {
    t0 = 0.0;
    period = 0.5;
  }
  const int count = tiny ? 3 : 6;
  std::vector<double> moments;
  for (int k = 0; k < count; ++k) moments.push_back(t0 + k * period / count);
  say(o, "fig5: simulating " + file.string() + " to " + seconds(t0 + period));
  const Run run = simulate(scene, moments, t0 + period, loadScene(file).output.fps);
  // The camera: in front of the bell (its centre of mass at mid-cycle, the arms below it) and the
  // nozzle pouring during the cycle with the first 3.5 m of its jet.
  const auto mid = std::min_element(run.time.begin(), run.time.end(), [&](double a, double b) {
    return std::abs(a - (t0 + period / 2)) < std::abs(b - (t0 + period / 2));
  });
  const Eigen::Vector3f bell = run.centre[size_t(mid - run.time.begin())].cast<float>();
  Eigen::Vector3f lo = bell - Eigen::Vector3f(4.0f, 3.0f, 7.0f), hi = bell + Eigen::Vector3f(4.0f, 0.0f, 3.0f);
  nlohmann::json pouring = nullptr;
  for (const sim::EmitterParams& e : faucets)
    if (e.start <= t0 + period && e.end >= t0) {
      const Eigen::Vector3f jet = e.position + 3.5f * e.direction.normalized();
      for (const Eigen::Vector3f& p : {e.position, jet}) {
        lo = lo.cwiseMin(p - Eigen::Vector3f::Constant(1.5f));
        hi = hi.cwiseMax(p + Eigen::Vector3f::Constant(1.5f));
      }
      pouring = {{"position", {e.position.x(), e.position.y(), e.position.z()}}, {"start_s", e.start}, {"end_s", e.end}};
      break;
    }
  lo.y() = hi.y() = bell.y();
  const float fov = 45.0f;
  FramedView view = frameFromFront(lo, hi, float(level.jellyfish.x()) / float(level.jellyfish.y()), fov);
  // The eye level with the jet, 1 m below the nozzle, so that it sees the falling stream through
  // air above the water's front face, not through the water from below.
  if (!pouring.is_null()) view.position.z() = std::max(view.position.z(), float(pouring["position"][2]) - 1.0f);
  scene.render.cameraKeys.clear();
  scene.render.camera.position = view.position;
  scene.render.camera.lookAt = view.lookAt;
  scene.render.camera.up = Eigen::Vector3f::UnitZ();
  scene.render.camera.verticalFovDegrees = fov;
  std::vector<render::Image> stills;
  for (size_t f = 0; f < run.frames.size(); ++f) {
    say(o, "fig5: rendering jellyfish.json at " + seconds(run.moments[f]));
    stills.push_back(labelled(renderStill(scene, run.frames[f], run.moments[f]), int(f) + 1, run.moments[f],
                              level.textScale));
  }
  const render::Image strip = besideEachOther(stills, level.gap);
  const render::Image plot = drawPlot(
      forcePlot(run, t0, t0 + period, "time in the cycle (s)", "ring force per spring (N)", strip.width()),
      o.outDir / "fig5_force.png", written);
  const fs::path figure = o.outDir / "fig5_jellyfish.png";
  writePng(aboveEachOther({strip, plot}, level.gap), figure);
  written.insert(written.end() - 4, figure);
  return {{"file", figure.filename().string()},
          {"plot", "fig5_force.png"},
          {"scenes", {file.string()}},
          {"cycle_s", {t0, t0 + period}},
          {"moments_s", run.moments},
          {"faucet", pouring},
          {"layout", "frames 1-" + std::to_string(run.moments.size()) +
                         " over one pulse cycle, left to right, above the ring muscle's applied force per spring "
                         "over the cycle (markers: the frames' moments)"},
          {"camera", cameraJson(scene.render.camera)}};
}

}  // namespace

const char* figureQualityName(FigureQuality quality) {
  switch (quality) {
    case FigureQuality::Tiny: return "tiny";
    case FigureQuality::Preview: return "preview";
    case FigureQuality::Final: return "final";
  }
  return "?";
}

FigureQuality parseFigureQuality(const std::string& name) {
  for (FigureQuality q : {FigureQuality::Tiny, FigureQuality::Preview, FigureQuality::Final})
    if (name == figureQualityName(q)) return q;
  throw std::invalid_argument("expected tiny, preview or final, got " + name);
}

const std::vector<std::string>& figureNames() {
  static const std::vector<std::string> names{"fig2", "fig3", "fig5"};
  return names;
}

std::vector<fs::path> writeFigures(const FigureOptions& options) {
  for (const std::string& name : options.only)
    if (std::find(figureNames().begin(), figureNames().end(), name) == figureNames().end())
      throw std::invalid_argument("no figure " + name + " (fig2, fig3 or fig5)");
  const FigureLevel level = figureLevel(options.quality);
  fs::create_directories(options.outDir);
  std::vector<fs::path> written;
  nlohmann::json record = {{"quality", figureQualityName(options.quality)}, {"figures", nlohmann::json::object()}};
  for (const auto& [name, integrator] : kIntegrator)
    if (integrator == level.integrator) record["render"] = {{"integrator", name}, {"samples", level.samples}};
  const auto start = std::chrono::steady_clock::now();
  using Maker = nlohmann::json (*)(const FigureOptions&, const FigureLevel&, std::vector<fs::path>&);
  const std::pair<const char*, Maker> makers[] = {{"fig2", figure2}, {"fig3", figure3}, {"fig5", figure5}};
  for (const auto& [name, make] : makers) {
    if (!options.only.empty() && std::find(options.only.begin(), options.only.end(), name) == options.only.end())
      continue;
    const auto begun = std::chrono::steady_clock::now();
    nlohmann::json entry = make(options, level, written);
    entry["wall_s"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - begun).count();
    record["figures"][name] = std::move(entry);
  }
  record["wall_s"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const fs::path json = options.outDir / "figures.json";
  writeTextAtomic(json, record.dump(2) + "\n");
  written.push_back(json);
  return written;
}

render::Image besideEachOther(const std::vector<render::Image>& images, int gap, const Eigen::Vector4f& background) {
  int width = 0, height = 0;
  for (const render::Image& i : images) {
    width += i.width() + (width > 0 ? gap : 0);
    height = std::max(height, i.height());
  }
  render::Image out(std::max(width, 1), std::max(height, 1), background);
  int x0 = 0;
  for (const render::Image& i : images) {
    for (int y = 0; y < i.height(); ++y)
      for (int x = 0; x < i.width(); ++x) out.at(x0 + x, y) = i.at(x, y);
    x0 += i.width() + gap;
  }
  return out;
}

render::Image aboveEachOther(const std::vector<render::Image>& images, int gap, const Eigen::Vector4f& background) {
  int width = 0, height = 0;
  for (const render::Image& i : images) {
    height += i.height() + (height > 0 ? gap : 0);
    width = std::max(width, i.width());
  }
  render::Image out(std::max(width, 1), std::max(height, 1), background);
  int y0 = 0;
  for (const render::Image& i : images) {
    const int x0 = (width - i.width()) / 2;
    for (int y = 0; y < i.height(); ++y)
      for (int x = 0; x < i.width(); ++x) out.at(x0 + x, y0 + y) = i.at(x, y);
    y0 += i.height() + gap;
  }
  return out;
}

FramedView frameFromFront(const Eigen::Vector3f& lo, const Eigen::Vector3f& hi, float aspect, float fovDegrees,
                          float margin) {
  const Eigen::Vector3f middle = 0.5f * (lo + hi);
  const float halfHeight = 0.5f * (hi.z() - lo.z()) * (1.0f + 2.0f * margin);
  const float halfWidth = 0.5f * (hi.x() - lo.x()) * (1.0f + 2.0f * margin);
  const float tanHalf = std::tan(0.5f * fovDegrees * std::numbers::pi_v<float> / 180.0f);
  const float distance = std::max(halfHeight / tanHalf, halfWidth / (tanHalf * aspect));
  return {Eigen::Vector3f(middle.x(), lo.y() - distance, middle.z()), middle};
}

}  // namespace kurage::pipeline
