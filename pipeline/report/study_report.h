// OUT/report.html for a study (pipeline/studies/study.h): the study's figure (error against the
// timed seconds, or seconds by run), drawn inline as SVG (pipeline/report/svg_plot.h), the cheapest
// setting within the accepted error, and a table of every run with its knob values, status,
// error, the measure's figures, seconds, steps and particles; failed runs are listed in a
// warnings box with their messages. While the study runs, runs not done yet are "pending" and the
// page reloads itself (pipeline/report/page.h); it links OUT's study.csv, study.md and study.png.
#pragma once

#include "pipeline/studies/study.h"

#include <filesystem>
#include <string>
#include <vector>

namespace kurage::pipeline {

// The page, with `rows` the runs done so far (in the study's order); `running`: more are to come.
std::string studyReportHtml(const Study& study, const std::vector<StudyRow>& rows, const std::filesystem::path& outDir,
                            bool running);

// OUT/report.html, written atomically.
void writeStudyReport(const Study& study, const std::vector<StudyRow>& rows, const std::filesystem::path& outDir,
                      bool running);

}  // namespace kurage::pipeline
