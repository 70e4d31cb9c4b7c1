#include "pipeline/report/study_report.h"

#include "pipeline/io/files.h"
#include "pipeline/io/process.h"
#include "pipeline/report/html.h"
#include "pipeline/report/page.h"
#include "pipeline/report/svg_plot.h"

#include <sstream>

namespace kurage::pipeline {

namespace fs = std::filesystem;

std::string studyReportHtml(const Study& study, const std::vector<StudyRow>& rows, const fs::path& outDir,
                            bool running) {
  const auto settings = studySettings(study);
  const auto combos = studyCombinations(settings);
  const bool scored = study.measure->scored();
  PageHead head;
  head.title = study.name + " · kurage study";
  head.refresh = running;
  // A run of a study can take long: the page says the study may have stopped only well past the
  // longest run so far.
  for (const StudyRow& r : rows) head.quietSeconds = std::max(head.quietSeconds, 3.0 * r.totalSeconds + 60.0);
  size_t failed = 0;
  for (const StudyRow& r : rows) failed += !r.ok;

  std::ostringstream o;
  o << pageStart(head) << "<header>\n<h1>Study: " << escapeHtml(study.name) << "</h1>\n";
  if (!study.description.empty()) o << "<p class=\"lead\">" << escapeHtml(study.description) << "</p>\n";
  o << "<p class=\"status " << (running ? "running" : failed == rows.size() && !rows.empty() ? "failed" : "complete")
    << "\"><span class=\"pill\">" << (running ? "running" : "complete") << "</span> " << rows.size() << " of "
    << combos.size() << " runs done";
  if (running) o << " <progress id=\"progress\" value=\"" << rows.size() << "\" max=\"" << combos.size() << "\"></progress>";
  if (failed) o << ", " << failed << " failed";
  o << " · base scene <code>" << escapeHtml(study.scene) << "</code>, measure <code>" << escapeHtml(study.measure->name)
    << "</code>, " << escapeHtml(formatNumber(study.duration, 4)) << " s simulated";
  if (scored) o << ", accepted error " << escapeHtml(formatNumber(study.errorThreshold, 3));
  o << "</p>\n</header>\n";

  if (failed) {
    o << "<section id=\"warnings\" class=\"warnings\">\n<h2>" << failed << (failed == 1 ? " run" : " runs")
      << " failed</h2>\n<ul>\n";
    for (const StudyRow& r : rows)
      if (!r.ok) o << "<li>" << escapeHtml(studyRunLabel(study, r)) << ": " << escapeHtml(r.message) << "</li>\n";
    o << "</ul>\n</section>\n";
  }

  o << "<section id=\"figure\">\n<h2>" << (scored ? "Accuracy against time" : "Time by run") << "</h2>\n";
  Plot plot = studyPlot(study, rows);
  plot.width = 960;
  plot.height = 540;
  o << "<figure class=\"wide\">" << svgPlot(plot, "study") << "</figure>\n";
  if (scored && !running) {
    const StudyVerdict v = studyVerdict(study, rows);
    o << "<p>";
    if (v.cheapest)
      o << "<b>Cheapest setting within the accepted error: " << escapeHtml(studyRunLabel(study, *v.cheapest)) << "</b>, error "
        << escapeHtml(formatNumber(v.cheapest->error, 3)) << " in " << escapeHtml(formatDuration(v.cheapest->totalSeconds)) << ".";
    else if (v.best)
      o << "<b>No setting reaches the accepted error</b>; the smallest is " << escapeHtml(formatNumber(v.best->error, 3))
        << " with " << escapeHtml(studyRunLabel(study, *v.best)) << ".";
    else
      o << "<b>Every run failed.</b>";
    o << "</p>\n";
  }
  o << "</section>\n";

  o << "<section id=\"runs\">\n<h2>Runs</h2>\n<table class=\"data\">\n<tr>";
  for (const StudyKnob& k : study.knobs) o << "<th>" << escapeHtml(k.name) << "</th>";
  o << "<th>status</th>";
  if (scored) o << "<th>error</th>";
  for (const std::string& f : study.measure->figures) o << "<th>" << escapeHtml(f) << "</th>";
  o << "<th>seconds (" << escapeHtml(study.measure->timedName()) << ")</th><th>steps</th><th>particles</th></tr>\n";
  const size_t columns = study.knobs.size() + 4 + (scored ? 1 : 0) + study.measure->figures.size();
  for (size_t c = 0; c < combos.size(); ++c) {
    if (c < rows.size()) {
      const StudyRow& r = rows[c];
      o << "<tr class=\"" << (r.ok ? "ok" : "failed") << "\">";
      for (const std::string& l : r.knobLabels) o << "<td>" << escapeHtml(l) << "</td>";
      if (!r.ok) {
        o << "<td colspan=\"" << columns - study.knobs.size() << "\">failed: " << escapeHtml(r.message) << "</td></tr>\n";
        continue;
      }
      o << "<td>ok</td>";
      if (scored) o << "<td>" << escapeHtml(formatNumber(r.error, 3)) << "</td>";
      for (double f : r.figures) o << "<td>" << escapeHtml(formatNumber(f, 4)) << "</td>";
      o << "<td>" << escapeHtml(formatNumber(r.totalSeconds, 3)) << "</td><td>" << r.steps << "</td><td>" << r.particles
        << "</td></tr>\n";
    } else {
      o << "<tr class=\"pending\">";
      for (size_t k = 0; k < combos[c].size(); ++k) o << "<td>" << escapeHtml(settings[k][combos[c][k]].label) << "</td>";
      o << "<td colspan=\"" << columns - study.knobs.size() << "\">" << (c == rows.size() ? "running" : "pending")
        << "</td></tr>\n";
    }
  }
  o << "</table>\n";
  o << "<p class=\"note\">Files: ";
  bool any = false;
  for (const char* file : {"study.csv", "study.md", "study.png", "study.svg", "study.pdf", "study.gp"})
    if (fs::exists(outDir / file)) {
      o << (any ? " · " : "") << "<a href=\"" << file << "\">" << file << "</a>";
      any = true;
    }
  if (!any) o << "written when the study ends";
  o << "</p>\n</section>\n";
  o << pageEnd(head, "kurage study " + shellWord(study.file.string(), false) + " -o " + shellWord(outDir.string(), false), "made it");
  return o.str();
}

void writeStudyReport(const Study& study, const std::vector<StudyRow>& rows, const fs::path& outDir, bool running) {
  writeTextAtomic(outDir / "report.html", studyReportHtml(study, rows, outDir, running));
}

}  // namespace kurage::pipeline
