// Study files: loading and validating a study and every scene it will run (pipeline/studies/study.h).
// Kept apart from running studies so that the loader is small enough to fuzz (tests/fuzz).
#include "pipeline/studies/study.h"

#include "pipeline/io/files.h"

#include <algorithm>
#include <string>

namespace kurage::pipeline {

namespace fs = std::filesystem;

namespace {

// The study file's "measure": the names of the registered measures.
const EnumTable<const StudyMeasure*>& measureNames() {
  static const EnumTable<const StudyMeasure*> table = [] {
    EnumTable<const StudyMeasure*> t;
    for (const StudyMeasure& m : studyMeasures()) t.emplace_back(m.name, &m);
    return t;
  }();
  return table;
}

}  // namespace

// ---- The study file's registry (strict loading with pipeline/param_visitor.h) ----

template <class V>
void describe(V& v, StudyVariant& p) {
  v.value("label", p.label, {"", "the variant's name in the CSV, the plot and the summary", {}, true});
  v.value("set", p.set, {"", "scene values it sets: {\"json.path\": value, ...}", {}, true});
  v.value("series", p.series,
          {"", "plot of a one-knob study: variants naming the same series are joined by one line, named in the "
               "legend, each point labelled with its label less the series' name (e.g. \"path\" and \"path, 4 spp\")"});
}

template <class V>
void describe(V& v, StudyKnob& p) {
  v.value("name", p.name, {"", "column and label name (default: the path)"});
  v.value("path", p.path, {"", "JSON path into the scene, e.g. \"time_step.fixed_step\" or \"bodies[0].spacing\""});
  nlohmann::json raw;
  v.value("values", raw, {"", "the values the path takes, one run each"});
  if (!raw.is_null()) {
    if (!raw.is_array() || raw.empty()) v.fail("values", "must be a non-empty array, got " + jsonExcerpt(raw));
    p.values.assign(raw.begin(), raw.end());
  }
  v.list("variants", p.variants, {"", "instead of path and values: labelled sets of scene values"});
}

template <class V>
void describe(V& v, Study& s) {
  v.ignore("$schema");
  v.value("name", s.name, {"", "study name"});
  v.value("description", s.description, {"", "what it measures and how its scene differs from the committed ones"});
  v.value("scene", s.scene, {"", "base scene file, relative to the study file's folder", {}, true});
  v.value("set", s.set, {"", "scene values set in every run before the knobs: {\"json.path\": value, ...}"});
  v.list("knobs", s.knobs, {"", "one or two knobs; the runs are every combination of their values", {}, true});
  v.enumeration("measure", s.measure, measureNames(),
                {"", "the error measure (pipeline/studies/study_measures.h; `kurage study --help`)", {}, true});
  v.value("duration", s.duration, {"s", "simulated time of each run", nonNegative(), true});
  v.value("error_threshold", s.errorThreshold, {"", "the accepted error, in the measure's unit", nonNegative()});
  v.value("reference_data", s.referenceData, {"", "dam break: Martin & Moyce CSV, relative to the study file"});
  v.value("average_from", s.averageFrom, {"s", "buoyancy, hydrostatic_tank: average from this time", nonNegative()});
  v.value("sample_interval", s.sampleInterval, {"s", "buoyancy, hydrostatic_tank: time between samples", positive()});
  v.value("body", s.body, {"", "buoyancy, membrane_leak: index of the body", between(0, 1000)});
  v.value("rays", s.rays, {"", "surface_distance: rays from the particles' centroid", between(1, 1000000)});
  v.value("reference_samples", s.referenceSamples, {"", "render_rmse: samples per pixel of the reference", between(1, 65536)});
  v.value("reference_max_depth", s.referenceMaxDepth, {"", "render_rmse: max depth of the reference", between(1, 1024)});
  v.value("reference_set", s.referenceSet,
          {"", "render_rmse: scene values the reference sets besides samples, depth and seed: {\"json.path\": value, ...}"});
  v.value("repeat", s.repeat,
          {"", "runs per setting, keeping the fastest: the error is the same every time (runs are deterministic), "
               "the wall time is not", between(1, 100)});
}

// ---- JSON paths ----

void setJsonPath(nlohmann::json& document, const std::string& path, const nlohmann::json& value) {
  if (path.empty()) throw std::invalid_argument("an empty JSON path");
  nlohmann::json* at = &document;
  size_t i = 0;
  std::string walked;
  while (i < path.size()) {
    if (path[i] == '[') {
      const size_t close = path.find(']', i);
      if (close == std::string::npos || close == i + 1)
        throw std::invalid_argument("\"" + path + "\": expected an index in [ ] at " + std::to_string(i));
      const std::string digits = path.substr(i + 1, close - i - 1);
      if (digits.find_first_not_of("0123456789") != std::string::npos)
        throw std::invalid_argument("\"" + path + "\": [" + digits + "] is not an index");
      const size_t index = std::stoul(digits);
      if (!at->is_array())
        throw std::invalid_argument("\"" + path + "\": " + (walked.empty() ? "the scene" : walked) + " is not an array");
      if (index >= at->size())
        throw std::invalid_argument("\"" + path + "\": " + walked + " has " + std::to_string(at->size()) +
                                    " element(s), no [" + digits + "]");
      at = &(*at)[index];
      walked += "[" + digits + "]";
      i = close + 1;
      if (i < path.size() && path[i] != '.' && path[i] != '[')
        throw std::invalid_argument("\"" + path + "\": expected . or [ after ]");
      if (i < path.size() && path[i] == '.') ++i;
      continue;
    }
    size_t end = path.find_first_of(".[", i);
    if (end == std::string::npos) end = path.size();
    const std::string key = path.substr(i, end - i);
    if (key.empty()) throw std::invalid_argument("\"" + path + "\": an empty key at " + std::to_string(i));
    if (at->is_null()) *at = nlohmann::json::object();
    if (!at->is_object())
      throw std::invalid_argument("\"" + path + "\": " + (walked.empty() ? "the scene" : walked) + " is not an object");
    at = &(*at)[key];
    walked += (walked.empty() ? "" : ".") + key;
    i = end;
    if (i < path.size() && path[i] == '.') {
      ++i;
      if (i == path.size()) throw std::invalid_argument("\"" + path + "\": ends with .");
    }
  }
  *at = value;
}

namespace {

std::string labelOf(const nlohmann::json& value) {
  if (value.is_string()) return value.get<std::string>();
  return value.dump();
}

nlohmann::json readJsonFile(const fs::path& file) { return parseStrictJson(readFile(file), file.string()); }

}  // namespace

std::vector<std::vector<KnobSetting>> studySettings(const Study& study) {
  std::vector<std::vector<KnobSetting>> out;
  for (const StudyKnob& k : study.knobs) out.push_back(knobSettings(k));
  return out;
}

std::vector<std::vector<size_t>> studyCombinations(const std::vector<std::vector<KnobSetting>>& settings) {
  std::vector<std::vector<size_t>> out{{}};
  for (const auto& knob : settings) {
    std::vector<std::vector<size_t>> next;
    for (size_t v = 0; v < knob.size(); ++v)
      for (const auto& prefix : out) {
        std::vector<size_t> c = prefix;
        c.push_back(v);
        next.push_back(std::move(c));
      }
    out = std::move(next);
  }
  // Reorder so that the first knob varies fastest: sort by the later knobs first.
  std::stable_sort(out.begin(), out.end(), [](const auto& a, const auto& b) {
    for (size_t k = a.size(); k-- > 0;)
      if (a[k] != b[k]) return a[k] < b[k];
    return false;
  });
  return out;
}

fs::path studyPath(const Study& study, const std::string& relative) {
  const fs::path p(relative);
  return p.is_absolute() ? p : study.file.parent_path() / p;
}

std::vector<KnobSetting> knobSettings(const StudyKnob& knob) {
  std::vector<KnobSetting> out;
  for (const nlohmann::json& v : knob.values) out.push_back({labelOf(v), "", {{knob.path, v}}});
  for (const StudyVariant& variant : knob.variants) {
    KnobSetting s{variant.label, variant.series, {}};
    for (const auto& [path, value] : variant.set.items()) s.set.emplace_back(path, value);
    out.push_back(std::move(s));
  }
  return out;
}

nlohmann::json studyRunScene(const Study& study, const std::vector<const KnobSetting*>& settings) {
  nlohmann::json scene = readJsonFile(studyPath(study, study.scene));
  for (const auto& [path, value] : study.set.items()) setJsonPath(scene, path, value);
  for (const KnobSetting* s : settings)
    for (const auto& [path, value] : s->set) setJsonPath(scene, path, value);
  return scene;
}

Study parseStudy(const nlohmann::json& document, const fs::path& file) {
  const std::string name = file.string();
  if (!document.is_object()) throw SceneError(name, "", "a study must be a JSON object");
  Study study;
  JsonReader reader(document, name, "");
  describe(reader, study);
  reader.finish();
  study.file = file;
  auto fail = [&name](const std::string& path, const std::string& message) { throw SceneError(name, path, message); };

  if (!study.set.is_object()) fail("set", "must be an object of JSON paths and values, got " + jsonExcerpt(study.set));
  if (study.knobs.empty() || study.knobs.size() > 2) fail("knobs", "must hold one or two knobs");
  for (size_t k = 0; k < study.knobs.size(); ++k) {
    StudyKnob& knob = study.knobs[k];
    const std::string path = "knobs[" + std::to_string(k) + "]";
    const bool byPath = !knob.path.empty() || !knob.values.empty();
    if (byPath && !knob.variants.empty()) fail(path, "give either path and values or variants, not both");
    if (!byPath && knob.variants.empty()) fail(path, "needs path and values, or variants");
    if (byPath && knob.path.empty()) fail(path + ".path", "is required with values");
    if (byPath && knob.values.empty()) fail(path + ".values", "is required with path");
    for (size_t i = 0; i < knob.variants.size(); ++i)
      if (!knob.variants[i].set.is_object())
        fail(path + ".variants[" + std::to_string(i) + "].set", "must be an object of JSON paths and values");
    if (knob.name.empty()) knob.name = byPath ? knob.path : "variant";
  }
  if (study.measure->scored() && study.errorThreshold < 0.0)
    fail("error_threshold", "is required for the measure " + std::string(study.measure->name));
  if (const auto problem = study.measure->checkStudy(study)) fail(problem->first, problem->second);

  // The base scene, then every knob value alone, then every combination, as scenes.
  const fs::path sceneFile = studyPath(study, study.scene);
  std::error_code error;  // a name too long for the file system is no scene file either, not a throw
  if (!fs::is_regular_file(sceneFile, error)) fail("scene", "no scene file " + sceneFile.string());
  loadScene(sceneFile);  // the base scene's own errors name the scene file
  const std::string sceneName = sceneFile.string();
  // `pathPath`: where a JSON path that does not fit the scene is named.
  auto check = [&](const std::string& studyPath, const std::vector<const KnobSetting*>& settings,
                   const std::string& pathPath) {
    nlohmann::json doc;
    try {
      doc = studyRunScene(study, settings);
    } catch (const std::invalid_argument& e) {
      fail(pathPath, e.what());
    }
    try {
      const Scene scene = parseScene(doc, sceneName);
      const std::string problem = study.measure->checkScene(study, scene);
      if (!problem.empty()) fail(studyPath, problem);
    } catch (const SceneError& e) {
      if (e.file() == name) throw;
      fail(studyPath, "the scene refuses it: " + std::string(e.what()));
    }
  };
  check("set", {}, "set");
  if (!study.referenceSet.is_object()) fail("reference_set", "must be an object of JSON paths and values");
  if (!study.referenceSet.empty()) {  // the reference of the base scene must be a valid scene
    nlohmann::json doc = studyRunScene(study, {});
    try {
      for (const auto& [path, value] : study.referenceSet.items()) setJsonPath(doc, path, value);
    } catch (const std::invalid_argument& e) {
      fail("reference_set", e.what());
    }
    try {
      parseScene(doc, sceneName);
    } catch (const SceneError& e) {
      fail("reference_set", "the scene refuses it: " + std::string(e.what()));
    }
  }
  const auto settings = studySettings(study);
  for (size_t k = 0; k < settings.size(); ++k)
    for (size_t i = 0; i < settings[k].size(); ++i) {
      const StudyKnob& knob = study.knobs[k];
      const std::string knobPath = "knobs[" + std::to_string(k) + "]";
      const std::string path = knobPath + (knob.variants.empty() ? ".values[" : ".variants[") + std::to_string(i) + "]";
      check(path, {&settings[k][i]}, knob.variants.empty() ? knobPath + ".path" : path + ".set");
    }
  if (settings.size() > 1)
    for (const auto& combo : studyCombinations(settings)) {
      std::vector<const KnobSetting*> chosen;
      std::string labels;
      for (size_t k = 0; k < combo.size(); ++k) {
        chosen.push_back(&settings[k][combo[k]]);
        labels += (labels.empty() ? "" : ", ") + study.knobs[k].name + " = " + settings[k][combo[k]].label;
      }
      check("knobs (" + labels + ")", chosen, "knobs");
    }
  return study;
}

Study loadStudy(const fs::path& file) {
  std::string text;
  try {
    text = readFile(file);
  } catch (const IoError& e) {
    throw SceneError(file.string(), "", std::string("cannot read the study file: ") + e.what());
  }
  return parseStudy(parseStrictJson(text, file.string()), file.string());
}

}  // namespace kurage::pipeline
