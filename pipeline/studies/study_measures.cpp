// The measures' registry and what each needs of a study and its scenes (study_measures.h); their
// scorers, which run the stages, are study_scorers.cpp, so that loading a study runs and links none.
#include "pipeline/studies/study_measures.h"

#include "pipeline/analysis/dam_break.h"
#include "pipeline/studies/study.h"

#include <stdexcept>

namespace kurage::pipeline {

namespace {

using StudyProblem = std::optional<std::pair<std::string, std::string>>;

StudyProblem anyStudy(const Study&) { return std::nullopt; }
std::string anyScene(const Study&, const Scene&) { return {}; }

StudyProblem averageWithinDuration(const Study& study) {
  if (study.averageFrom > study.duration) return std::make_pair("average_from", "must not be after the duration");
  return std::nullopt;
}

std::string needsBody(const Study& study, const Scene& scene) {
  if (size_t(study.body) < scene.sim.bodies.size()) return {};
  return "body " + std::to_string(study.body) + " is not in the scene (it has " +
         std::to_string(scene.sim.bodies.size()) + " bodies)";
}

// ---- dam_break_front, dam_break_column ----

StudyProblem damBreakReference(const Study& study) {
  if (study.referenceData.empty())
    return std::make_pair("reference_data", "is required for a dam break (the Martin & Moyce CSV)");
  try {
    loadMartinMoyce(studyPath(study, study.referenceData));
  } catch (const std::exception& e) {
    return std::make_pair("reference_data", std::string(e.what()));
  }
  return std::nullopt;
}

std::string damBreakScene(const Study&, const Scene& scene) {
  if (scene.sim.fluidBlocks.empty()) return "a dam break needs fluid_blocks[0] (the column)";
  if (scene.sim.gravity.norm() <= 0.0f) return "a dam break needs gravity";
  return {};
}

// ---- hydrostatic_tank ----

std::string stillTankScene(const Study&, const Scene& scene) {
  if (scene.sim.fluidBlocks.empty()) return "a still tank needs fluid_blocks[0] (its filled height)";
  if (scene.sim.gravity.norm() <= 0.0f) return "a still tank needs gravity";
  return {};
}

}  // namespace

const char* StudyMeasure::timedName() const {
  switch (timed) {
    case StudyTimed::Surfacing: return "surfacing";
    case StudyTimed::Rendering: return "rendering";
    case StudyTimed::Simulation: break;
  }
  return "simulation";
}

const std::vector<StudyMeasure>& studyMeasures() {
  static const std::vector<StudyMeasure> measures{
      {"dam_break_front",
       "mean relative error of the surge front against Martin & Moyce (1952), `reference_data`; the column is "
       "fluid_blocks[0] standing at container.min.x",
       "surge front, mean relative error vs Martin & Moyce", "surge front error", StudyTimed::Simulation,
       {"front_error", "column_error", "front_points", "column_points"}, damBreakReference, damBreakScene},
      {"dam_break_column", "the same for the residual column's height",
       "column height, mean relative error vs Martin & Moyce", "column height error", StudyTimed::Simulation,
       {"front_error", "column_error", "front_points", "column_points"}, damBreakReference, damBreakScene},
      {"buoyancy",
       "|submerged fraction of bodies[body], averaged from `average_from` to the end every `sample_interval`, - its "
       "specific gravity| (Archimedes)",
       "|submerged fraction - specific gravity|", "|fraction - s.g.|", StudyTimed::Simulation,
       {"submerged_fraction", "specific_gravity", "samples"}, averageWithinDuration, needsBody},
      {"membrane_leak", "fluid particles below the membrane bodies[body] at the end",
       "fluid particles through the membrane", "particles through", StudyTimed::Simulation,
       {"leaked", "fluid", "leaked_fraction", "collision_cap_hits"}, anyStudy, needsBody},
      {"surface_distance",
       "mean distance (m) of the fluid's level set at `duration` (0: the initial particle lattice) from the exact "
       "metaball surface, along `rays` rays; times surfacing",
       "mean distance from the exact surface (m)", "mean distance (m)", StudyTimed::Surfacing,
       {"max_m", "rms_m", "rays", "misses", "active_voxels", "memory_mb"}, anyStudy, anyScene},
      {"render_rmse",
       "RMSE (sRGB, 0..1) of the frame at `duration` against the same frame rendered with `reference_samples` "
       "samples, depth `reference_max_depth`, another seed and the values of `reference_set`; times rendering "
       "(runs that differ only in render keys share the simulation and the surfaces)",
       "RMSE vs reference (sRGB)", "RMSE (sRGB)", StudyTimed::Rendering, {"total_mrays", "reference_seconds"},
       anyStudy, anyScene},
      {"density_error",
       "the fluid's mean compression over the run (each step's mean over fluid particles of max(rho - rho0, 0) / "
       "rho0, averaged over the steps; the largest step's is a figure)",
       "mean compression of the fluid over the run, fraction of rho0", "mean density error", StudyTimed::Simulation,
       {"max_density_error", "steps"}, anyStudy, anyScene},
      {"hydrostatic_tank",
       "a still tank filled to fluid_blocks[0]'s top: the worst interior slab's |p / (rho0 g depth) - 1|, slabs two "
       "spacings thick (pipeline/analysis/still_tank.h), averaged over the samples from `average_from` every "
       "`sample_interval`",
       "worst interior slab's |p / (rho0 g depth) - 1|, slabs two spacings thick, averaged over the samples",
       "worst slab pressure error", StudyTimed::Simulation,
       {"surface_error", "rms_speed", "worst_slab_below_filled", "slabs", "samples", "mean_iterations",
        "worst_slab_against_weight", "worst_layer"},
       averageWithinDuration, stillTankScene},
      {"none", "no error: the simulation's time only (what switching an effect off saves)", "", "",
       StudyTimed::Simulation, {}, anyStudy, anyScene}};
  return measures;
}

const StudyMeasure* findStudyMeasure(std::string_view name) {
  for (const StudyMeasure& m : studyMeasures())
    if (name == m.name) return &m;
  return nullptr;
}

}  // namespace kurage::pipeline
