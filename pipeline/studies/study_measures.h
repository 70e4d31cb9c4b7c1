// The measures a study scores its runs with (a study file's "measure"), one registration each in
// study_measures.cpp: its name, what it scores and against which reference, the columns it adds
// to study.csv, the stage whose wall time the study reports, and what it needs of the study file
// and of each run's scene (checked when the study is loaded, before anything runs); its scorer,
// which runs the stages, is registered by the same name in study_scorers.cpp. The measures
// themselves are pipeline/analysis/; `kurage study --help` lists these with their descriptions.
//
// Adding a measure: an entry in studyMeasures() and its scorer in study_scorers.cpp (a test checks
// that every measure has one); the loader, the runner, study.csv, study.md and the figure read
// everything else from the entry.
#pragma once

#include "pipeline/scene.h"
#include "sim/simulation.h"

#include <nlohmann/json.hpp>

#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace kurage::pipeline {

struct Study;
struct StudyRow;

// The stage whose wall time a study reports for each run (study.csv's total_s).
enum class StudyTimed { Simulation, Surfacing, Rendering };

// Scores one run of a study: sets row.error, row.figures (the measure's columns), the seconds of
// the stages it ran and row.totalSeconds (those of the timed stage). `doc` is the run's scene as
// JSON, `scene` the same parsed. Throws to fail the run (the message goes into its row).
using StudyScorer = std::function<void(const nlohmann::json& doc, const Scene& scene, StudyRow& row)>;

struct StudyMeasure {
  const char* name;
  const char* description;  // what it scores, against what, and what it needs
  const char* errorUnit;    // what the error is (study.md, the figure's title); "": timing only
  const char* errorAxis;    // the figure's error axis
  StudyTimed timed;
  std::vector<std::string> figures;  // its own columns of study.csv, in order
  // The study file's own requirements beyond its keys: {JSON path, message} for the first unmet.
  std::optional<std::pair<std::string, std::string>> (*checkStudy)(const Study& study);
  // What it needs of each run's scene: a message, or "" when the scene has it.
  std::string (*checkScene)(const Study& study, const Scene& scene);

  bool scored() const { return *errorUnit != '\0'; }
  const char* timedName() const;  // "simulation", "surfacing" or "rendering"
};

// Every measure, in the order `kurage study --help` lists them.
const std::vector<StudyMeasure>& studyMeasures();
// The measure named `name`; nullptr for another name.
const StudyMeasure* findStudyMeasure(std::string_view name);

// The scorer of one study's runs (study_scorers.cpp, in kurage_pipeline with the stages); it may
// keep what the runs share (the reference data, a simulation that runs differing only in surface
// or render keys reuse). Throws std::logic_error for a measure without a scorer.
StudyScorer startStudyScorer(const Study& study);
// Whether the measure named `measure` has a scorer.
bool hasStudyScorer(std::string_view measure);

}  // namespace kurage::pipeline
