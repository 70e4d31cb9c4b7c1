// Progress of long work: items done of total, rate and ETA, redrawn on one line of stderr when
// enabled (the CLI enables it when stderr is a terminal, or with --progress), and told to an
// observer when one is given (the run's report page, pipeline/report/run_report.h), whether or
// not the line is drawn.
#pragma once

#include <chrono>
#include <functional>
#include <string>

namespace kurage::pipeline {

// Where a stage stands: `done` of `total` items, `seconds` since the stage started and the
// estimated seconds left at the rate so far (negative: not known yet); the simulation's time
// steps so far (negative: another stage); the seconds left in the whole run (negative: not known;
// pipeline/estimate.h: RunForecast).
struct ProgressState {
  std::string stage;
  int done = 0;
  int total = 0;
  double seconds = 0.0;
  double secondsLeft = -1.0;
  long long steps = -1;
  double runSecondsLeft = -1.0;
};
using ProgressObserver = std::function<void(const ProgressState&)>;

class Progress {
public:
  Progress(std::string label, int total, bool enabled, ProgressObserver observer = {});
  ~Progress();
  void advance(int done, long long steps = -1);  // items finished so far (and the sim's steps)
  void finish();

private:
  std::string label_;
  int total_;
  bool enabled_;
  ProgressObserver observer_;
  bool finished_ = false;
  int first_ = -1;  // the first count advance() was given: the rate counts items done here
  std::chrono::steady_clock::time_point start_;
};

}  // namespace kurage::pipeline
