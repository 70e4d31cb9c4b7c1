#include "pipeline/studies/study.h"

#include "pipeline/io/csv.h"
#include "pipeline/io/files.h"
#include "pipeline/io/plot.h"
#include "pipeline/thread_limit.h"
#include "sim/simulation.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>
#include <sstream>

namespace kurage::pipeline {

namespace fs = std::filesystem;
namespace {

// ---- Output ----

std::string number(double v) {
  if (!std::isfinite(v)) return "";
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.6g", v);
  return buffer;
}

// Three significant digits; whole numbers below 10^7 as they are (2000, not 2e+03).
std::string shortNumber(double v) {
  char buffer[32];
  if (std::isfinite(v) && v == std::round(v) && std::fabs(v) < 1e7) std::snprintf(buffer, sizeof buffer, "%.0f", v);
  else std::snprintf(buffer, sizeof buffer, "%.3g", v);
  return buffer;
}

// The step phases (sim::StepPhase) that ran in any row.
std::vector<size_t> phasesUsed(const std::vector<StudyRow>& rows) {
  std::vector<size_t> used;
  for (size_t s = 0; s < size_t(sim::StepPhase::Count); ++s)
    for (const StudyRow& r : rows)
      if (s < r.simPhases.size() && r.simPhases[s] > 0.0) {
        used.push_back(s);
        break;
      }
  return used;
}

bool timesSurface(const StudyMeasure& m) { return m.timed != StudyTimed::Simulation; }
bool timesRender(const StudyMeasure& m) { return m.timed == StudyTimed::Rendering; }

std::string studyCsv(const Study& study, const std::vector<StudyRow>& rows) {
  const std::vector<std::string>& figures = study.measure->figures;
  const std::vector<size_t> phases = phasesUsed(rows);
  std::ostringstream csv;
  for (const StudyKnob& k : study.knobs) csv << csvField(k.name) << ",";
  csv << "status,error";
  for (const std::string& f : figures) csv << "," << f;
  csv << ",total_s,sim_s";
  for (size_t s : phases) csv << ",sim_" << sim::phaseName(sim::StepPhase(s)) << "_s";
  if (timesSurface(*study.measure)) csv << ",surface_s";
  if (timesRender(*study.measure)) csv << ",render_s";
  csv << ",steps,particles,message\n";
  for (const StudyRow& r : rows) {
    for (const std::string& label : r.knobLabels) csv << csvField(label) << ",";
    csv << (r.ok ? "ok" : "failed") << "," << (r.ok && study.measure->scored() ? number(r.error) : "");
    for (size_t f = 0; f < figures.size(); ++f) csv << "," << (f < r.figures.size() ? number(r.figures[f]) : "");
    csv << "," << number(r.totalSeconds) << "," << number(r.simSeconds);
    for (size_t s : phases) csv << "," << (s < r.simPhases.size() ? number(r.simPhases[s]) : "");
    if (timesSurface(*study.measure)) csv << "," << number(r.surfaceSeconds);
    if (timesRender(*study.measure)) csv << "," << number(r.renderSeconds);
    csv << "," << r.steps << "," << r.particles << "," << csvField(r.message) << "\n";
  }
  return csv.str();
}

// A log axis when every value is positive and they span a decade or more.
bool wantsLog(const std::vector<double>& values) {
  double lo = std::numeric_limits<double>::infinity(), hi = 0.0;
  for (double v : values) {
    if (!std::isfinite(v)) continue;
    if (v <= 0.0) return false;
    lo = std::min(lo, v);
    hi = std::max(hi, v);
  }
  return hi > 0.0 && hi >= 10.0 * lo;
}

std::string joinLabels(const Study& study, const StudyRow& r) { return studyRunLabel(study, r); }

std::string studyMarkdown(const Study& study, const std::vector<StudyRow>& rows, const StudyOptions& options) {
  const std::vector<std::string>& figures = study.measure->figures;
  std::ostringstream md;
  md << "# Study: " << study.name << "\n\n";
  if (!study.description.empty()) md << study.description << "\n\n";
  // The command that regenerates the table, on a line of its own (docs/README.md, "Conventions").
  md << "Command: `kurage study " << study.file.generic_string() << " -o OUT";
  if (options.threads > 0) md << " --threads " << options.threads;
  md << "`\n\nBase scene `" << study.scene << "`, measure `" << study.measure->name << "`";
  if (study.measure->scored()) md << " (" << study.measure->errorUnit << ")";
  md << ", " << shortNumber(study.duration) << " s simulated";
  if (study.measure->scored()) md << ", accepted error " << shortNumber(study.errorThreshold);
  md << "; the time is the wall time of " << study.measure->timedName();
  if (study.repeat > 1) md << ", the fastest of " << study.repeat << " runs";
  md << ".\n\n";

  if (!study.measure->scored()) {
    // What each variant costs, step phase by phase, against the first run.
    const std::vector<size_t> phases = phasesUsed(rows);
    md << "| run | sim s | steps | saves vs first |";
    for (size_t s : phases) md << " " << sim::phaseName(sim::StepPhase(s)) << " s (share) |";
    md << "\n| --- | ---: | ---: | ---: |";
    for (size_t s = 0; s < phases.size(); ++s) md << " ---: |";
    md << "\n";
    const double base = rows.empty() ? 0.0 : rows.front().totalSeconds;
    for (const StudyRow& r : rows) {
      md << "| " << joinLabels(study, r) << " | ";
      if (!r.ok) {
        md << "failed: " << r.message << " |\n";
        continue;
      }
      double stepSum = 0.0;
      for (double v : r.simPhases) stepSum += v;
      md << shortNumber(r.totalSeconds) << " | " << r.steps << " | ";
      if (&r == &rows.front() || base <= 0.0) md << "";
      else if (r.totalSeconds <= base)
        md << shortNumber(base - r.totalSeconds) << " s (" << shortNumber(100.0 * (base - r.totalSeconds) / base) << " %)";
      else
        md << "costs " << shortNumber(r.totalSeconds - base) << " s more (" << shortNumber(r.totalSeconds / base) << " times)";
      md << " |";
      for (size_t s : phases) {
        const double v = s < r.simPhases.size() ? r.simPhases[s] : 0.0;
        md << " " << (v > 0.0 ? shortNumber(v) + " (" + shortNumber(100.0 * v / stepSum) + " %)" : "-") << " |";
      }
      md << "\n";
    }
    return md.str();
  }

  md << "| run | error |";
  for (const std::string& f : figures) md << " " << f << " |";
  md << " seconds | steps | status |\n| --- | ---: |";
  for (size_t f = 0; f < figures.size(); ++f) md << " ---: |";
  md << " ---: | ---: | --- |\n";
  const auto [cheapest, best, dearest] = studyVerdict(study, rows);
  for (const StudyRow& r : rows) {
    md << "| " << joinLabels(study, r) << " | ";
    if (!r.ok) {
      md << " |";
      for (size_t f = 0; f < figures.size(); ++f) md << " |";
      md << " | | failed: " << r.message << " |\n";
      continue;
    }
    md << shortNumber(r.error) << " |";
    for (size_t f = 0; f < figures.size(); ++f) md << " " << (f < r.figures.size() ? shortNumber(r.figures[f]) : "") << " |";
    md << " " << shortNumber(r.totalSeconds) << " | " << r.steps << " | ok |\n";
  }
  md << "\n";
  if (cheapest) {
    md << "**Cheapest setting within the accepted error (" << shortNumber(study.errorThreshold) << "): "
       << joinLabels(study, *cheapest) << "**, error " << shortNumber(cheapest->error) << " in "
       << shortNumber(cheapest->totalSeconds) << " s";
    if (dearest && dearest != cheapest && cheapest->totalSeconds > 0.0)
      md << " (" << shortNumber(dearest->totalSeconds / cheapest->totalSeconds) << " times less than the dearest run, "
         << joinLabels(study, *dearest) << ")";
    md << ".\n";
  } else if (best) {
    md << "**No setting reaches the accepted error (" << shortNumber(study.errorThreshold) << ")**; the smallest error is "
       << shortNumber(best->error) << " with " << joinLabels(study, *best) << " in " << shortNumber(best->totalSeconds)
       << " s.\n";
  } else {
    md << "**Every run failed.**\n";
  }
  return md.str();
}

}  // namespace

std::string studyRunLabel(const Study& study, const StudyRow& r) {
  std::string out;
  for (size_t k = 0; k < r.knobLabels.size() && k < study.knobs.size(); ++k)
    out += (out.empty() ? "" : ", ") + study.knobs[k].name + " = " + r.knobLabels[k];
  return out;
}

StudyVerdict studyVerdict(const Study& study, const std::vector<StudyRow>& rows) {
  StudyVerdict v;
  for (const StudyRow& r : rows) {
    if (!r.ok) continue;
    if (r.error <= study.errorThreshold && (!v.cheapest || r.totalSeconds < v.cheapest->totalSeconds)) v.cheapest = &r;
    if (!v.best || r.error < v.best->error) v.best = &r;
    if (!v.dearest || r.totalSeconds > v.dearest->totalSeconds) v.dearest = &r;
  }
  return v;
}

Plot studyPlot(const Study& study, const std::vector<StudyRow>& rows) {
  Plot plot;
  plot.title = study.name;
  plot.width = 900;
  plot.height = 560;
  if (!study.measure->scored()) {
    // Timing only: the seconds of each run, in the order of the runs, and of the step phases that
    // take at least 5 % of some run.
    plot.title = study.name + ": simulation seconds by run and step phase";
    plot.x.label = "run";
    plot.y.label = "seconds";
    PlotSeries total;
    total.label = "total";
    total.lines = false;
    total.markers = true;
    total.markerSize = 1.4;
    std::vector<double> ys;
    for (size_t i = 0; i < rows.size(); ++i) {
      if (!rows[i].ok) continue;
      total.x.push_back(double(i + 1));
      total.y.push_back(rows[i].totalSeconds);
      ys.push_back(rows[i].totalSeconds);
      std::string label;
      for (const std::string& l : rows[i].knobLabels) label += (label.empty() ? "" : ", ") + l;
      total.pointLabels.push_back(label);
    }
    plot.series.push_back(std::move(total));
    double offset = -0.12;  // phases side by side to the right of each run's total
    for (size_t phase : phasesUsed(rows)) {
      bool large = false;
      for (const StudyRow& r : rows)
        if (r.ok && phase < r.simPhases.size() && r.simPhases[phase] >= 0.05 * r.totalSeconds) large = true;
      if (!large) continue;
      PlotSeries s;
      s.label = std::string(sim::phaseName(sim::StepPhase(phase)));
      s.lines = false;
      s.markers = true;
      s.markerSize = 0.8;
      for (size_t i = 0; i < rows.size(); ++i)
        if (rows[i].ok && phase < rows[i].simPhases.size()) {
          s.x.push_back(double(i + 1) + offset);
          s.y.push_back(rows[i].simPhases[phase]);
          ys.push_back(rows[i].simPhases[phase]);
        }
      plot.series.push_back(std::move(s));
      offset -= 0.04;
    }
    plot.x.min = 0.0;
    plot.x.max = double(rows.size()) + 2.0;
    plot.y.log = wantsLog(ys);
    if (!plot.y.log) plot.y.min = 0.0;
    return plot;
  }
  // The title names the measure and the failed runs (not drawn); writePlot wraps it to fit.
  size_t failed = 0;
  for (const StudyRow& r : rows) failed += !r.ok;
  const std::string failures = failed ? " (" + std::to_string(failed) + " failed: study.csv)" : "";
  plot.title = study.name + ": " + study.measure->errorUnit + failures;
  plot.x.label = std::string("seconds (") + study.measure->timedName() + ")";
  plot.y.label = study.measure->errorAxis;
  std::vector<double> xs, ys;
  for (const StudyRow& r : rows)
    if (r.ok) {
      xs.push_back(r.totalSeconds);
      ys.push_back(r.error);
    }
  plot.x.log = wantsLog(xs);
  plot.y.log = wantsLog(ys);
  // One line per value of the second knob, points labelled with the first knob's value; in a
  // one-knob study whose variants name series, one line per series, each point labelled with its
  // label less the series' name; otherwise one line.
  const std::vector<KnobSetting> first = knobSettings(study.knobs[0]);
  const bool twoKnobs = study.knobs.size() > 1;
  const bool named = !twoKnobs && std::any_of(first.begin(), first.end(), [](const KnobSetting& k) { return !k.series.empty(); });
  std::vector<std::string> lines;  // each line's key, in order
  if (twoKnobs)
    for (const KnobSetting& k : knobSettings(study.knobs[1])) lines.push_back(k.label);
  else
    for (const KnobSetting& k : first)
      if (std::find(lines.begin(), lines.end(), k.series) == lines.end()) lines.push_back(k.series);
  const auto lineOf = [&](const StudyRow& r) -> std::string {
    if (twoKnobs) return r.knobLabels[1];
    const auto k = std::find_if(first.begin(), first.end(), [&](const KnobSetting& s) { return s.label == r.knobLabels[0]; });
    return k == first.end() ? std::string() : k->series;
  };
  for (const std::string& key : lines) {
    PlotSeries s;
    s.markers = true;
    s.label = twoKnobs ? study.knobs[1].name + " = " + key : key.empty() ? study.knobs[0].name : key;
    for (const StudyRow& r : rows) {
      if (!r.ok || lineOf(r) != key) continue;
      s.x.push_back(r.totalSeconds);
      s.y.push_back(r.error);
      std::string point = r.knobLabels[0];
      if (named && !key.empty() && point.rfind(key, 0) == 0) {
        point.erase(0, key.size());
        point.erase(0, point.find_first_not_of(", "));
      }
      s.pointLabels.push_back(point);
    }
    plot.series.push_back(std::move(s));
  }
  if (!xs.empty()) {
    PlotSeries line;
    line.label = "accepted error " + shortNumber(study.errorThreshold);
    line.colour = Eigen::Vector3f(0.5f, 0.5f, 0.5f);
    line.lineWidth = 1.0;
    const double lo = *std::min_element(xs.begin(), xs.end()), hi = *std::max_element(xs.begin(), xs.end());
    line.x = {lo, hi};
    line.y = {study.errorThreshold, study.errorThreshold};
    plot.series.push_back(std::move(line));
  }
  return plot;
}

void writeStudyPlot(const Study& study, const std::vector<StudyRow>& rows, const fs::path& file) {
  writePlot(studyPlot(study, rows), file);
}

std::vector<StudyRow> studyRowsFromCsv(const Study& study, const std::string& csv, const std::string& file) {
  std::istringstream in(csv);
  std::string line;
  if (!std::getline(in, line)) throw std::runtime_error(file + ": empty");
  const std::vector<std::string> header = csvRecord(line);
  auto column = [&](const std::string& name) -> std::optional<size_t> {
    for (size_t i = 0; i < header.size(); ++i)
      if (header[i] == name) return i;
    return std::nullopt;
  };
  for (const char* required : {"status", "error", "total_s", "sim_s", "steps", "particles", "message"})
    if (!column(required)) throw std::runtime_error(file + ": no column '" + required + "': not a study.csv");
  for (const StudyKnob& k : study.knobs)
    if (!column(k.name)) throw std::runtime_error(file + ": no column '" + k.name + "' (the study's knob)");
  const std::vector<std::string>& figures = study.measure->figures;
  auto number = [&](const std::vector<std::string>& f, std::optional<size_t> c) {
    return c && *c < f.size() && !f[*c].empty() ? std::stod(f[*c]) : 0.0;
  };
  std::vector<StudyRow> rows;
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    const std::vector<std::string> f = csvRecord(line);
    if (f.size() != header.size())
      throw std::runtime_error(file + ": line " + std::to_string(rows.size() + 2) + " has " + std::to_string(f.size()) +
                               " fields, the header " + std::to_string(header.size()));
    StudyRow r;
    for (const StudyKnob& k : study.knobs) r.knobLabels.push_back(f[*column(k.name)]);
    r.ok = f[*column("status")] == "ok";
    r.error = number(f, column("error"));
    for (const std::string& name : figures) r.figures.push_back(number(f, column(name)));
    r.simPhases.assign(size_t(sim::StepPhase::Count), 0.0);
    for (size_t s = 0; s < size_t(sim::StepPhase::Count); ++s)
      r.simPhases[s] = number(f, column("sim_" + std::string(sim::phaseName(sim::StepPhase(s))) + "_s"));
    r.totalSeconds = number(f, column("total_s"));
    r.simSeconds = number(f, column("sim_s"));
    r.surfaceSeconds = number(f, column("surface_s"));
    r.renderSeconds = number(f, column("render_s"));
    r.steps = uint64_t(number(f, column("steps")));
    r.particles = size_t(number(f, column("particles")));
    r.message = f[*column("message")];
    rows.push_back(std::move(r));
  }
  return rows;
}

std::vector<StudyRow> runStudy(const Study& study, const StudyOptions& options) {
  ThreadLimit limit(options.threads);
  fs::create_directories(options.outDir);
  const auto settings = studySettings(study);
  const auto combos = studyCombinations(settings);
  const std::string sceneName = studyPath(study, study.scene).string();
  const StudyScorer score = startStudyScorer(study);
  std::vector<StudyRow> rows;
  for (size_t c = 0; c < combos.size(); ++c) {
    std::vector<const KnobSetting*> chosen;
    StudyRow row;
    for (size_t k = 0; k < combos[c].size(); ++k) {
      chosen.push_back(&settings[k][combos[c][k]]);
      row.knobLabels.push_back(chosen.back()->label);
    }
    const nlohmann::json doc = studyRunScene(study, chosen);
    const Scene scene = parseScene(doc, sceneName);
    for (int attempt = 0; attempt < study.repeat; ++attempt) {
      StudyRow again;
      again.knobLabels = row.knobLabels;
      try {
        score(doc, scene, again);
        again.ok = true;
      } catch (const sim::SimulationError& e) {
        again.message = std::string("simulation stopped: ") + e.what();
      } catch (const std::exception& e) {
        again.message = std::string("error: ") + e.what();
      }
      if (attempt == 0 || (again.ok && again.totalSeconds < row.totalSeconds)) row = std::move(again);
      if (!row.ok) break;
    }
    if (options.progress)
      std::fprintf(stderr, "study %s: run %zu/%zu (%s): %s\n", study.name.c_str(), c + 1, combos.size(),
                   joinLabels(study, row).c_str(),
                   row.ok ? ((!study.measure->scored() ? std::string() : "error " + shortNumber(row.error) + ", ") +
                             shortNumber(row.totalSeconds) + " s")
                                .c_str()
                          : row.message.c_str());
    rows.push_back(std::move(row));
    if (options.onRun) options.onRun(rows);
  }
  writeTextAtomic(options.outDir / "study.csv", studyCsv(study, rows));
  writeStudyPlot(study, rows, options.outDir / "study.png");
  writeTextAtomic(options.outDir / "study.md", studyMarkdown(study, rows, options));
  return rows;
}

}  // namespace kurage::pipeline
