// Studies: what accuracy costs in time. A study file names a base scene, one or two knobs (each
// a JSON path into the scene with a list of values, or a list of labelled variants that set
// several paths at once), an error measure against a reference, the simulated duration and the
// error the user accepts. `kurage study STUDY.json -o OUT` runs every combination of the knob
// values and writes, atomically:
//   OUT/study.csv  one row per run: knob values, status, error, the measure's own figures, wall
//                  seconds per stage (each phase of the simulation step from sim::SimStats, surfacing,
//                  rendering) and the total of the timed stages
//   OUT/study.png  error against the timed seconds (log axes where the data spans a decade or
//                  more), each point labelled with its knob value, the accepted error as a line
//   OUT/study.md   the runs as a table and the cheapest setting within the accepted error
//
// Knobs edit the scene's JSON before it is parsed, so every scene key is a knob
// ("time_step.fixed_step", "bodies[0].spacing", "render.samples"), and every combination is
// validated as a scene before anything runs: a bad study or a knob value the scene refuses is a
// SceneError naming the study file and the JSON path (exit 2). A run that fails (a
// SimulationError, ...) is a row with the message, not the end of the study. `repeat` runs each
// setting several times and keeps the fastest: runs are deterministic, wall times are not.
//
// Measures: pipeline/studies/study_measures.h, one registration each; `kurage study --help`
// lists them.
#pragma once

#include "pipeline/io/plot.h"
#include "pipeline/param_visitor.h"
#include "pipeline/scene.h"
#include "pipeline/studies/study_measures.h"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace kurage::pipeline {

// A knob variant: a label and the scene values it sets, {"json.path": value, ...}.
struct StudyVariant {
  std::string label;
  std::string series;  // plot: variants of one series share a line (empty: the knob's line)
  nlohmann::json set = nlohmann::json::object();
};

struct StudyKnob {
  std::string name;  // CSV column and plot label; default: the path
  std::string path;  // a JSON path into the scene, with `values`
  std::vector<nlohmann::json> values;
  std::vector<StudyVariant> variants;  // instead of path and values
};

// One value of a knob, resolved: its label and what it sets.
struct KnobSetting {
  std::string label;
  std::string series;  // StudyVariant::series (empty for values)
  std::vector<std::pair<std::string, nlohmann::json>> set;
};
std::vector<KnobSetting> knobSettings(const StudyKnob& knob);

struct Study {
  std::string name = "study";
  std::string description;
  std::string scene;  // the base scene, relative to the study file's folder
  nlohmann::json set = nlohmann::json::object();  // applied to the base scene before the knobs
  std::vector<StudyKnob> knobs;  // one or two; runs are every combination
  const StudyMeasure* measure = findStudyMeasure("none");
  float duration = 0.0f;        // simulated seconds
  double errorThreshold = -1.0;  // the accepted error (required unless the measure is none)
  std::string referenceData;     // dam break: the Martin & Moyce CSV, relative to the study file's folder
  float averageFrom = -1.0f;     // buoyancy, hydrostatic_tank: s; < 0 = half the duration
  float sampleInterval = 0.5f;   // buoyancy, hydrostatic_tank: s between samples
  int body = 0;                  // buoyancy, membrane_leak: bodies[body]
  int rays = 2000;               // surface_distance
  int referenceSamples = 256;    // render_rmse
  int referenceMaxDepth = 16;    // render_rmse
  // render_rmse: scene values the reference sets after samples, depth and seed, {"json.path":
  // value, ...} (e.g. the integrator, so that runs of other integrators share one reference).
  nlohmann::json referenceSet = nlohmann::json::object();
  int repeat = 1;  // runs per setting; the row keeps the fastest (runs are deterministic, times are not)

  std::filesystem::path file;  // where it was loaded from (for relative paths and messages)
};

// Loads and validates a study and every scene it will run. Throws SceneError naming the file
// (the study's, or the base scene's for an invalid base) and the JSON path.
Study loadStudy(const std::filesystem::path& file);
Study parseStudy(const nlohmann::json& document, const std::filesystem::path& file);

// Sets the value at a JSON path ("a.b[2].c") of a document, creating missing object keys (an
// unknown key is then refused by the scene loader). Throws std::invalid_argument for a malformed
// path, an index past the end of an array, or a step into a value of the wrong type.
void setJsonPath(nlohmann::json& document, const std::string& path, const nlohmann::json& value);

// A path of the study file (its scene, its reference data): relative to the study file's folder.
std::filesystem::path studyPath(const Study& study, const std::string& relative);
// The knob settings, one list per knob; every combination of one setting per knob (indices into
// those lists), the first knob varying fastest.
std::vector<std::vector<KnobSetting>> studySettings(const Study& study);
std::vector<std::vector<size_t>> studyCombinations(const std::vector<std::vector<KnobSetting>>& settings);

// The scene of one run: the base scene's JSON with the study's `set` and the knob settings applied.
nlohmann::json studyRunScene(const Study& study, const std::vector<const KnobSetting*>& settings);

struct StudyRow;
struct StudyOptions {
  std::filesystem::path outDir;
  int threads = 0;  // 0: all cores
  bool progress = true;  // a line per run on stderr
  // Told after each run, with the rows so far (the study's report page follows them).
  std::function<void(const std::vector<StudyRow>& rowsSoFar)> onRun;
};

// One row of study.csv.
struct StudyRow {
  std::vector<std::string> knobLabels;
  bool ok = false;
  std::string message;  // why the run failed
  double error = 0.0;
  std::vector<double> figures;     // the measure's own columns (StudyMeasure::figures)
  std::vector<double> simPhases;   // seconds per sim::StepPhase
  double simSeconds = 0.0, surfaceSeconds = 0.0, renderSeconds = 0.0;
  double totalSeconds = 0.0;  // of the stages the measure times
  uint64_t steps = 0;
  size_t particles = 0;
};

// Runs the study and writes OUT/study.csv, study.png and study.md. Returns the rows.
std::vector<StudyRow> runStudy(const Study& study, const StudyOptions& options);

// The rows of a study.csv that runStudy wrote for `study` (for redrawing its figure). Throws
// std::runtime_error naming `file` when the CSV does not fit the study.
std::vector<StudyRow> studyRowsFromCsv(const Study& study, const std::string& csv, const std::string& file);
// "knob = label, knob = label" for a run.
std::string studyRunLabel(const Study& study, const StudyRow& row);

// Among the runs that succeeded: the cheapest whose error is within the accepted one, the one with
// the smallest error, and the slowest (null where there is none).
struct StudyVerdict {
  const StudyRow* cheapest = nullptr;
  const StudyRow* best = nullptr;
  const StudyRow* dearest = nullptr;
};
StudyVerdict studyVerdict(const Study& study, const std::vector<StudyRow>& rows);

// The study's figure: error against time (or seconds by run for a study without a measure).
Plot studyPlot(const Study& study, const std::vector<StudyRow>& rows);
// That figure as FILE.png, .svg, .pdf and .gp.
void writeStudyPlot(const Study& study, const std::vector<StudyRow>& rows, const std::filesystem::path& file);


}  // namespace kurage::pipeline
