#include "pipeline/progress.h"

#include <cstdio>

namespace kurage::pipeline {

Progress::Progress(std::string label, int total, bool enabled, ProgressObserver observer)
    : label_(std::move(label)), total_(total), enabled_(enabled), observer_(std::move(observer)),
      start_(std::chrono::steady_clock::now()) {
  if (observer_) observer_({label_, 0, total_, 0.0, -1.0});
  start_ = std::chrono::steady_clock::now();  // the observer's work (a page written) is not the first item's
}

Progress::~Progress() { finish(); }

void Progress::advance(int done, long long steps) {
  if (!enabled_ && !observer_) return;
  // A resumed stage starts part-way: items done before it started do not count towards the rate.
  if (first_ < 0) first_ = done - 1;
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const double rate = seconds > 0 ? (done - first_) / seconds : 0.0;
  const double eta = rate > 0 ? (total_ - done) / rate : -1.0;
  if (observer_) observer_({label_, done, total_, seconds, eta, steps});
  if (!enabled_) return;
  std::fprintf(stderr, "\r%-8s %5d/%-5d frames  %6.2f frames/s  ETA %3d:%02d ", label_.c_str(), done, total_, rate,
               eta > 0 ? int(eta) / 60 : 0, eta > 0 ? int(eta) % 60 : 0);
  std::fflush(stderr);
}

void Progress::finish() {
  if (!enabled_ || finished_) return;
  finished_ = true;
  std::fprintf(stderr, "\n");
}

}  // namespace kurage::pipeline
