// kurage study STUDY.json -o OUT: what accuracy costs in time (pipeline/studies/study.h).
#include "pipeline/commands/cli.h"
#include "pipeline/io/files.h"
#include "pipeline/report/study_report.h"
#include "pipeline/studies/study.h"

#include <algorithm>
#include <cstdio>
#include <sstream>
#include <string>

namespace kurage::pipeline {

namespace {

// "  name               description", the description wrapped at 100 columns under itself.
void printMeasure(const StudyMeasure& m) {
  std::string line = "  " + std::string(m.name);
  line.resize(std::max<size_t>(line.size() + 1, 21), ' ');
  const size_t indent = line.size();
  std::istringstream words(m.description);
  std::string word;
  bool first = true;
  while (words >> word) {
    if (!first && line.size() + 1 + word.size() > 100) {
      std::printf("%s\n", line.c_str());
      line.assign(indent, ' ');
      first = true;
    }
    line += (first ? "" : " ") + word;
    first = false;
  }
  std::printf("%s\n", line.c_str());
}

}  // namespace

int commandStudy(std::vector<std::string> rawArgs) {
  ArgParser args("study", std::move(rawArgs));
  if (args.flag({"-h", "--help"})) {
    std::printf(
        "usage: kurage study STUDY.json -o OUT [--threads N] [--quiet]\n"
        "       kurage study STUDY.json --check\n"
        "       kurage study STUDY.json --replot CSV -o FIGURE.png\n\n"
        "Runs a sweep: the study's base scene with every combination of its knob values, each run's\n"
        "error against a reference and its wall time per stage. Writes OUT/study.csv (one row per\n"
        "run), OUT/study.png (error against time, points labelled with the knob values) and\n"
        "OUT/study.md (a summary naming the cheapest setting within the study's accepted error), and\n"
        "OUT/report.html (the figure and every run's status as a page, kept current while it runs).\n"
        "The study file and every scene it makes are validated before anything runs (exit 2 with\n"
        "the file and JSON path); a run that fails is a row with its message. Studies are in\n"
        "scenes/studies/, their results in docs/results/data/studies/ (docs/results/accuracy.md).\n\n"
        "  -o, --output OUT   output folder (created if missing)\n"
        "  --check            validate the study and every scene it makes, run nothing\n"
        "  --replot CSV       redraw the figure of a study.csv made by this study (FIGURE.png, .svg,\n"
        "                     .pdf and the gnuplot script FIGURE.gp), run nothing\n"
        "  --threads N        worker threads (default: all cores)\n"
        "  --quiet            no line per run on stderr\n"
        "  -h, --help         this help\n\n"
        "measures (the study's \"measure\"):\n");
    for (const StudyMeasure& m : studyMeasures()) printMeasure(m);
    return 0;
  }
  StudyOptions options;
  const bool checkOnly = args.flag({"--check"});
  const std::optional<std::string> replot = args.option({"--replot"});
  if (auto out = args.option({"-o", "--output"})) options.outDir = *out;
  else if (!checkOnly) args.fail("missing -o OUT");
  if (auto t = args.intOption({"--threads"}, 1, 1024)) options.threads = *t;
  options.progress = !args.flag({"--quiet"});
  const std::vector<std::string> positional = args.positionals();
  if (positional.size() != 1) args.fail("expected one STUDY file");
  const Study study = loadStudy(positional[0]);
  if (replot) {
    const std::vector<StudyRow> rows = studyRowsFromCsv(study, readText(*replot), *replot);
    writeStudyPlot(study, rows, options.outDir);
    std::printf("figure: %s (and .svg, .pdf, .gp)\n", options.outDir.string().c_str());
    return 0;
  }
  if (checkOnly) {
    size_t runs = 1;
    for (const StudyKnob& k : study.knobs) runs *= knobSettings(k).size();
    std::printf("%s: valid (%zu runs)\n", positional[0].c_str(), runs);
    return 0;
  }
  // OUT/report.html follows the runs; a failure to write it is a warning, not the study's end.
  const auto report = [&](const std::vector<StudyRow>& rows, bool running) {
    try {
      writeStudyReport(study, rows, options.outDir, running);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "kurage: warning: the report page was not updated: %s\n", e.what());
    }
  };
  std::filesystem::create_directories(options.outDir);
  report({}, true);
  options.onRun = [&](const std::vector<StudyRow>& rows) { report(rows, true); };
  const std::vector<StudyRow> rows = runStudy(study, options);
  report(rows, false);
  size_t failed = 0;
  for (const StudyRow& r : rows) failed += !r.ok;
  std::printf("study: %s/study.md (%zu runs, %zu failed)\n", options.outDir.string().c_str(), rows.size(), failed);
  return 0;
}

}  // namespace kurage::pipeline
