#include "pipeline/estimate.h"

#include "pipeline/scene.h"
#include "sim/simulation.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace kurage::pipeline {

double RunEstimate::totalSeconds() const {
  double total = 0.0;
  for (double s : seconds) total += s;
  return total;
}

double stepsPerFrame(double frameInterval, double step) {
  if (!(step > 0.0) || !(frameInterval > 0.0)) return 0.0;
  const double ratio = frameInterval / step;
  const double whole = std::round(ratio);
  return std::abs(ratio - whole) <= 1e-6 * whole ? whole : std::ceil(ratio);
}

RunEstimate estimateRun(const RunSize& size, const MachineSpeed& speed) {
  RunEstimate e;
  e.steps = std::max(0.0, size.frames - 1.0) * stepsPerFrame(size.frameInterval, size.step);
  const double scale = double(speed.threads) / double(std::max(1, size.threads));
  const auto at = [&e](Stage s) -> double& { return e.seconds[size_t(s)]; };
  at(Stage::Sim) = scale * size.particles * e.steps * speed.simSecondsPerParticleStep;
  at(Stage::Surface) = scale * size.frames * speed.surfaceSecondsPerBlobVoxel *
                       (size.blobVoxels + speed.anisotropicSurfaceFactor * size.anisotropicBlobVoxels);
  at(Stage::Render) = scale * size.frames * size.pixels * size.samplesPerPixel *
                      (size.whitted ? speed.whittedSecondsPerSample : speed.pathSecondsPerSample);
  at(Stage::Encode) = size.video ? scale * size.frames * size.pixels * speed.encodeSecondsPerPixel : 0.0;
  return e;
}

RunSize runSize(const Scene& scene, const sim::Simulation& probe, int threads, bool video) {
  RunSize size;
  const sim::ParticleSet& particles = probe.particles();
  size.particles = double(particles.size());
  size.frames = scene.output.frameCount();
  size.frameInterval = 1.0 / double(scene.output.fps);
  const sim::TimeStepParams& ts = scene.sim.timeStep;
  size.step = ts.mode == sim::TimeStepMode::Fixed ? double(ts.fixedStep)
                                                  : std::min(double(ts.maxStep), double(probe.stabilityLimit().step));
  // Kind 0 is the fluid, kind b + 1 body b; chains are tubes, not surfaces (stages.h: surfaceFrame).
  const auto blob = [](const render::MetaballParams& m) { return std::pow(double(m.radius / m.voxelSize), 3.0); };
  for (size_t i = 0; i < particles.size(); ++i) {
    const int kind = particles.kind[i];
    const render::MetaballParams* params = nullptr;
    if (kind == 0)
      params = &scene.surface.fluid;
    else if (kind > 0 && size_t(kind) <= scene.sim.bodies.size() &&
             scene.sim.bodies[size_t(kind) - 1].shape != sim::BodyShape::Chain)
      params = &scene.surface.bodies;
    if (!params) continue;
    (params->kernel == render::MetaballKernel::Anisotropic ? size.anisotropicBlobVoxels : size.blobVoxels) +=
        blob(*params);
  }
  const render::RenderSettings& r = scene.render.settings;
  size.pixels = double(r.width) * double(r.height);
  size.samplesPerPixel = r.samplesPerPixel;
  size.whitted = r.integrator == render::IntegratorType::Whitted;
  size.video = video && scene.render.outputs.png;
  size.threads = threads;
  return size;
}

RunForecast::RunForecast(const RunEstimate& model) : left_(model.seconds) {}

void RunForecast::measured(Stage stage, double secondsPerFrame, double framesLeft) {
  left_[size_t(stage)] = std::max(0.0, secondsPerFrame * framesLeft);
  measured_[size_t(stage)] = true;
}

void RunForecast::finished(Stage stage) { measured(stage, 0.0, 0.0); }

std::string RunForecast::observe(ProgressState& p) {
  size_t index = 0;
  while (index < size_t(Stage::Count) && p.stage != kStageNames[index]) ++index;
  if (p.stage == "film") index = size_t(Stage::Encode);
  if (index == size_t(Stage::Count)) {  // another stage (export): not modelled
    p.runSecondsLeft = totalSecondsLeft();
    return "";
  }
  const Stage stage = Stage(index);
  for (size_t s = 0; s < index; ++s) finished(Stage(s));
  char what[160] = "";
  const double framesLeft = std::max(0, p.total - p.done);
  if (p.done >= p.total && p.done > 0) {
    finished(stage);
  } else if (p.done == 0) {
    // the stage's start: nothing measured
  } else if (stage == Stage::Sim) {
    if (simItems_ < 0) {
      simItems_ = p.done;
      simSeconds_ = p.seconds;
      simSteps_ = p.steps;
    } else {
      // the frames since the first report, at their mean seconds
      if (!measured_[index])
        std::snprintf(what, sizeof what, "sim frame %d: %lld steps in %.2f s", p.done - 1, p.steps - simSteps_,
                      p.seconds - simSeconds_);
      measured(stage, (p.seconds - simSeconds_) / double(p.done - simItems_), framesLeft);
    }
  } else if (!measured_[index]) {
    measured(stage, p.seconds / double(p.done), framesLeft);
    std::snprintf(what, sizeof what, "%s: first frame in %.2f s", p.stage.c_str(), p.seconds / double(p.done));
  } else if (p.secondsLeft >= 0.0) {
    left_[index] = p.secondsLeft;
  }
  p.runSecondsLeft = totalSecondsLeft();
  return what;
}

double RunForecast::secondsLeft(Stage stage) const { return left_[size_t(stage)]; }

double RunForecast::totalSecondsLeft() const {
  double total = 0.0;
  for (double s : left_) total += s;
  return total;
}

std::string RunForecast::line() const {
  std::string text;
  char part[96];
  for (size_t s = 0; s < size_t(Stage::Count); ++s) {
    std::snprintf(part, sizeof part, "%s%s %.1f min%s", s ? ", " : "", kStageNames[s], left_[s] / 60.0,
                  measured_[s] ? "" : " (model)");
    text += part;
  }
  std::snprintf(part, sizeof part, "; %.1f min in all", totalSecondsLeft() / 60.0);
  return text + part;
}

}  // namespace kurage::pipeline
