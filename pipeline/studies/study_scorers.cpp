// The measures' scorers (pipeline/studies/study_measures.h): each runs the stages a study's run
// needs and scores it against the measure's reference.
#include "pipeline/studies/study_measures.h"

#include "pipeline/analysis/body_measures.h"
#include "pipeline/analysis/dam_break.h"
#include "pipeline/analysis/still_tank.h"
#include "pipeline/analysis/surface_distance.h"
#include "pipeline/io/particle_cache.h"
#include "pipeline/stages.h"
#include "pipeline/studies/study.h"
#include "render/image.h"
#include "render/renderer.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <stdexcept>
#include <string_view>

namespace kurage::pipeline {

namespace {

// ---- What the scorers share ----

using Clock = std::chrono::steady_clock;
double secondsSince(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

// The parts of a scene's JSON that the simulation depends on (the key of the simulation cache),
// and those the surfaces depend on.
std::string simulationKey(nlohmann::json doc) {
  for (const char* k : {"$schema", "name", "description", "output", "surface", "render"}) doc.erase(k);
  return doc.dump();
}
std::string surfaceKey(const nlohmann::json& doc) {
  return simulationKey(doc) + (doc.contains("surface") ? doc["surface"].dump() : std::string());
}

struct SimOutcome {
  sim::ParticleSet particles;
  sim::SimStats stats;
  sim::SolverCounters solver;
  double seconds = 0.0;
  size_t capHits = 0;
};

// Runs the simulation to `duration`, calling `sample(sim)` at each of `times` (sorted, within
// the duration); sampling is not timed.
template <class Sample>
SimOutcome simulate(const Scene& scene, double duration, const std::vector<double>& times, Sample sample) {
  SimOutcome out;
  const auto start = Clock::now();
  sim::Simulation simulation(scene.sim);
  double seconds = secondsSince(start);
  for (double t : times) {
    const auto s = Clock::now();
    simulation.advanceTo(t);
    seconds += secondsSince(s);
    sample(simulation);
  }
  const auto s = Clock::now();
  simulation.advanceTo(duration);
  seconds += secondsSince(s);
  out.seconds = seconds;
  out.particles = simulation.particles();
  out.stats = simulation.stats();
  out.solver = simulation.solver().counters();
  if (const sim::BodySystem* bodies = simulation.bodies()) out.capHits = bodies->stats().capHits;
  return out;
}

SimOutcome simulateToEnd(const Scene& scene, double duration) {
  return simulate(scene, duration, {}, [](const sim::Simulation&) {});
}

// The run's simulation figures, and the simulation as the timed stage.
void takeSimFigures(StudyRow& row, const SimOutcome& sim) {
  row.simSeconds = sim.seconds;
  row.simPhases.assign(sim.stats.phaseSeconds.begin(), sim.stats.phaseSeconds.end());
  row.steps = sim.stats.steps;
  row.particles = sim.particles.size();
}
void timeSimulation(StudyRow& row, const SimOutcome& sim) {
  takeSimFigures(row, sim);
  row.totalSeconds = row.simSeconds;
}

// The simulation of the last run, reused while runs differ only in surface or render keys.
class SharedSimulation {
public:
  const SimOutcome& get(const nlohmann::json& doc, const Scene& scene, double duration) {
    const std::string key = simulationKey(doc);
    if (key_ != key || !sim_) {
      sim_ = simulateToEnd(scene, duration);
      key_ = key;
    }
    return *sim_;
  }

private:
  std::optional<SimOutcome> sim_;
  std::string key_;
};

ParticleFrame frameOf(const sim::ParticleSet& p, double time) {
  ParticleFrame f;
  f.time = time;
  f.px = p.x; f.py = p.y; f.pz = p.z;
  f.vx = p.vx; f.vy = p.vy; f.vz = p.vz;
  f.id = p.id;
  f.kind = p.kind;
  return f;
}

// The times from average_from (half the duration when not given) to the duration, every
// sample_interval.
std::vector<double> sampleTimes(const Study& study) {
  const double from = study.averageFrom < 0.0f ? 0.5 * study.duration : study.averageFrom;
  std::vector<double> times;
  for (int k = 0; from + k * double(study.sampleInterval) <= study.duration * (1.0 + 1e-9); ++k)
    times.push_back(std::min<double>(from + k * double(study.sampleInterval), study.duration));
  return times;
}

// ---- dam_break_front, dam_break_column ----

// Both series are figures; the error is the front's or the column's.
StudyScorer damBreak(const Study& study, bool front) {
  auto reference = std::make_shared<const MartinMoyce>(loadMartinMoyce(studyPath(study, study.referenceData)));
  return [&study, reference, front](const nlohmann::json&, const Scene& scene, StudyRow& row) {
    const sim::FluidBlock& block = scene.sim.fluidBlocks.front();
    DamBreakGeometry g;
    g.width = block.max.x() - block.min.x();
    g.height = block.max.z() - block.min.z();
    g.gravity = scene.sim.gravity.norm();
    g.spacing = scene.sim.fluid.spacing;
    g.origin = scene.sim.container.min.cast<double>();
    DamBreakTrack track(g);
    std::vector<double> times;  // every 0.05 in tau, as tests/test_dam_break.cpp
    for (int k = 1; track.timeAtTau(0.05 * k) < study.duration * (1.0 - 1e-9); ++k)
      times.push_back(track.timeAtTau(0.05 * k));
    times.push_back(study.duration);
    const SimOutcome sim = simulate(scene, study.duration, times,
                                    [&](const sim::Simulation& s) { track.record(s.particles(), s.time()); });
    timeSimulation(row, sim);
    const SeriesError frontError = meanRelativeError(track.front(), reference->surgeFront);
    const SeriesError columnError = meanRelativeError(track.column(), reference->columnHeight);
    row.figures = {frontError.meanRelative, columnError.meanRelative, double(frontError.points),
                   double(columnError.points)};
    const SeriesError& chosen = front ? frontError : columnError;
    if (chosen.points == 0) throw std::runtime_error("the run ends before the first reference point");
    row.error = chosen.meanRelative;
  };
}
StudyScorer damBreakFront(const Study& study) { return damBreak(study, true); }
StudyScorer damBreakColumn(const Study& study) { return damBreak(study, false); }

// ---- buoyancy ----

StudyScorer buoyancy(const Study& study) {
  return [&study](const nlohmann::json&, const Scene& scene, StudyRow& row) {
    const std::vector<double> times = sampleTimes(study);
    double sum = 0.0;
    const int kind = study.body + 1;
    const SimOutcome sim = simulate(scene, study.duration, times, [&](const sim::Simulation& s) {
      sum += submergedFraction(s.particles(), kind, scene.sim.fluid.spacing);
    });
    timeSimulation(row, sim);
    const double fraction = sum / double(times.size());
    const double gravity = scene.sim.bodies[size_t(study.body)].specificGravity;
    row.figures = {fraction, gravity, double(times.size())};
    row.error = std::fabs(fraction - gravity);
  };
}

// ---- membrane_leak ----

StudyScorer membraneLeakage(const Study& study) {
  return [&study](const nlohmann::json&, const Scene& scene, StudyRow& row) {
    const SimOutcome sim = simulateToEnd(scene, study.duration);
    timeSimulation(row, sim);
    const MembraneLeak leak = membraneLeak(sim.particles, study.body + 1, scene.sim.fluid.spacing);
    row.figures = {double(leak.leaked), double(leak.fluid),
                   leak.fluid ? double(leak.leaked) / double(leak.fluid) : 0.0, double(sim.capHits)};
    row.error = double(leak.leaked);
  };
}

// ---- surface_distance ----

StudyScorer surfaceDistanceScorer(const Study& study) {
  auto shared = std::make_shared<SharedSimulation>();
  return [&study, shared](const nlohmann::json& doc, const Scene& scene, StudyRow& row) {
    const SimOutcome& sim = shared->get(doc, scene, study.duration);
    takeSimFigures(row, sim);
    std::vector<Eigen::Vector3f> points;
    for (size_t i = 0; i < sim.particles.size(); ++i)
      if (sim.particles.kind[i] == 0) points.emplace_back(sim.particles.x[i], sim.particles.y[i], sim.particles.z[i]);
    if (points.empty()) throw std::runtime_error("no fluid particles to surface");
    // The fastest of three builds: surfacing takes milliseconds, where one build is noisy.
    render::LevelSet levelSet;
    double best = std::numeric_limits<double>::infinity();
    for (int k = 0; k < 3; ++k) {
      const auto start = Clock::now();
      levelSet = render::buildMetaballLevelSet(points, scene.surface.fluid);
      best = std::min(best, secondsSince(start));
    }
    row.surfaceSeconds = best;
    row.totalSeconds = best;
    const MetaballField field(points, scene.surface.fluid);
    const SurfaceDistance d = surfaceDistance(levelSet, field, scene.surface.fluid, study.rays);
    row.figures = {d.max, d.rms, double(d.rays), double(d.misses), double(levelSet.activeVoxelCount()),
                   double(levelSet.memoryBytes()) / 1e6};
    if (d.rays == 0) throw std::runtime_error("no ray crossed both surfaces");
    row.error = d.mean;
  };
}

// ---- render_rmse ----

// The surfaces and the reference frame, kept while the runs share them.
struct RenderShared {
  SharedSimulation simulation;
  std::string surfacesKey, referenceKey;
  std::map<std::string, render::LevelSet> surfaces;
  double surfaceSeconds = 0.0, referenceSeconds = 0.0;
  render::Image reference;
};

StudyScorer renderRmse(const Study& study) {
  auto shared = std::make_shared<RenderShared>();
  return [&study, shared](const nlohmann::json& doc, const Scene& scene, StudyRow& row) {
    RenderShared& c = *shared;
    const SimOutcome& sim = c.simulation.get(doc, scene, study.duration);
    takeSimFigures(row, sim);
    const std::string key = surfaceKey(doc);
    if (c.surfacesKey != key) {
      const auto start = Clock::now();
      c.surfaces = surfaceFrame(scene, frameOf(sim.particles, study.duration));
      c.surfaceSeconds = secondsSince(start);
      c.surfacesKey = key;
    }
    row.surfaceSeconds = c.surfaceSeconds;
    // The reference: the same scene with many samples, a deep path and another seed (so that its
    // noise is independent of the run's).
    nlohmann::json referenceDoc = doc;
    setJsonPath(referenceDoc, "render.samples", study.referenceSamples);
    setJsonPath(referenceDoc, "render.max_depth", study.referenceMaxDepth);
    const int seed = scene.render.settings.seed;
    setJsonPath(referenceDoc, "render.seed", seed == 2147483647 ? 0 : seed + 1);
    for (const auto& [path, value] : study.referenceSet.items()) setJsonPath(referenceDoc, path, value);
    const std::string referenceKey = key + referenceDoc["render"].dump();
    if (c.referenceKey != referenceKey) {
      const Scene referenceScene = parseScene(referenceDoc, "reference");
      const auto start = Clock::now();
      c.reference = renderSurfaces(referenceScene, c.surfaces, study.duration);
      c.referenceSeconds = secondsSince(start);
      c.referenceKey = referenceKey;
    }
    render::RenderStats stats;
    const auto start = Clock::now();
    const render::Image image = renderSurfaces(scene, c.surfaces, study.duration, &stats);
    row.renderSeconds = secondsSince(start);
    row.totalSeconds = row.renderSeconds;
    row.figures = {double(stats.totalRays) * 1e-6, c.referenceSeconds};
    row.error = render::imageRmse(image, c.reference);
  };
}

// ---- density_error ----

StudyScorer densityError(const Study& study) {
  return [&study](const nlohmann::json&, const Scene& scene, StudyRow& row) {
    const SimOutcome sim = simulateToEnd(scene, study.duration);
    timeSimulation(row, sim);
    const double steps = std::max<double>(1.0, double(sim.stats.steps));
    row.error = sim.stats.densityErrorSum / steps;
    row.figures = {sim.stats.densityErrorMax, double(sim.stats.steps)};
  };
}

// ---- hydrostatic_tank ----

StudyScorer stillTank(const Study& study) {
  return [&study](const nlohmann::json&, const Scene& scene, StudyRow& row) {
    const double filled = scene.sim.fluidBlocks.front().max.z() - scene.sim.container.min.z();
    HydrostaticTrack track(scene.sim, filled);
    const std::vector<double> times = sampleTimes(study);
    const SimOutcome sim =
        simulate(scene, study.duration, times, [&](const sim::Simulation& s) { track.record(s.particles()); });
    timeSimulation(row, sim);
    if (track.slabs() == 0) throw std::runtime_error("no interior slab: the tank is shallower than 4 h");
    const sim::SolverCounters& solver = sim.solver;
    const double iterations = solver.steps ? double(solver.iterations()) / double(solver.steps) : 0.0;
    row.figures = {track.surfaceError(), rmsSpeed(sim.particles, 0), track.worstSlabBelowFilled(), double(track.slabs()),
                   double(track.samples()), iterations, track.worstSlabAgainstWeight(), track.worstLayer()};
    row.error = track.worstSlab();
  };
}

// ---- none ----

StudyScorer timingOnly(const Study& study) {
  return [&study](const nlohmann::json&, const Scene& scene, StudyRow& row) {
    timeSimulation(row, simulateToEnd(scene, study.duration));
  };
}

using StartScorer = StudyScorer (*)(const Study&);

// One scorer per measure of studyMeasures(), by its name.
const std::map<std::string_view, StartScorer>& scorers() {
  static const std::map<std::string_view, StartScorer> table{
      {"dam_break_front", damBreakFront},
      {"dam_break_column", damBreakColumn},
      {"buoyancy", buoyancy},
      {"membrane_leak", membraneLeakage},
      {"surface_distance", surfaceDistanceScorer},
      {"render_rmse", renderRmse},
      {"density_error", densityError},
      {"hydrostatic_tank", stillTank},
      {"none", timingOnly}};
  return table;
}

}  // namespace

bool hasStudyScorer(std::string_view measure) { return scorers().count(measure) != 0; }

StudyScorer startStudyScorer(const Study& study) {
  const auto it = scorers().find(study.measure->name);
  if (it == scorers().end()) throw std::logic_error(std::string("no scorer for the measure ") + study.measure->name);
  return it->second(study);
}

}  // namespace kurage::pipeline
