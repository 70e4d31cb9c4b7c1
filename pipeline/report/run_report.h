// OUT/report.html: a run as one page, for a user who would rather look than read run.json. It is
// drawn from OUT alone (run.json, sim_frames.csv, bodies.csv, the frames and the film), so
// `kurage report OUT` redraws it for any run, and it opens from disk with no network: images and
// the film are linked by paths relative to OUT, plots are inline SVG (pipeline/report/svg_plot.h),
// styles are inline, and the only script is a running run's page's (pipeline/report/page.h).
//
// The page, top to bottom: the scene's name, its status (complete, running with the stage, frames
// done of total and the time left in the stage and in the run, failed or interrupted with the
// error, or stopped: "running" in run.json but no process holds OUT's lock); a warnings box
// where there is anything to warn of (run.json's stages.*.warnings: the solver's or the collision
// loop's cap hits, torn body particles; a failed run's error); the film (<video> of OUT/NAME.mp4) and a contact sheet
// of about 24 frames with their times; the run in brief (scene, command, frames, particles,
// bodies, the solver and its tolerances, time stepping, rendering, versions); where the time went
// (each stage's seconds, and each step phase's share of the simulation, as bars); the simulation
// over time (sim_frames.csv: step size, solver iterations and cap hits, density error, particle
// count, kinetic energy); the bodies over time (bodies.csv: muscle force and depth as in the
// paper's Fig. 3, rest-density factor, and for shells tilt, margin radius, apex height, diameter,
// fluid inside the wall; the swim summary); the outputs and what opens each.
//
// While a command runs (LiveRunReport) the page is rewritten at most every few seconds, at each
// stage's start and at its end; a running page reloads itself every 5 s and stops once the run's
// status is no longer "running" (or, after a minute without news, says the run may have stopped).
#pragma once

#include "pipeline/progress.h"

#include <chrono>
#include <filesystem>
#include <optional>
#include <string>

namespace kurage::pipeline {

// The page for OUT; `live`: where the stage this process runs stands (the page then refreshes
// itself). Reads everything before it returns. Throws std::runtime_error naming the file for a
// folder that is not a run (no OUT/run.json), a run.json that is not a run's record (not JSON,
// not an object with "parameters"), or a damaged sim_frames.csv or bodies.csv.
std::string runReportHtml(const std::filesystem::path& outDir, const std::optional<ProgressState>& live = {});

// OUT/report.html, written atomically (pipeline/io/files.h): a failure leaves the page before it.
void writeRunReport(const std::filesystem::path& outDir, const std::optional<ProgressState>& live = {});

// Keeps OUT/report.html current while a command runs. A failure to write the page is a warning on
// stderr, never the end of the run.
class LiveRunReport {
public:
  explicit LiveRunReport(std::filesystem::path outDir, double intervalSeconds = 2.0);
  // The observer for StageOptions::observer: rewrites the page with `state` at a stage's start
  // and end, and otherwise when `intervalSeconds` have passed since the last write.
  ProgressObserver observer();
  void update(const ProgressState& state);
  // The page as run.json now says (a finished run: no refresh).
  void finish();

private:
  void write(const std::optional<ProgressState>& state);
  std::filesystem::path outDir_;
  double interval_;
  std::chrono::steady_clock::time_point last_{};
  bool written_ = false;
};

}  // namespace kurage::pipeline
