// Progress of long work on stderr: items done of total, rate and ETA, redrawn on one line.
// Silent unless enabled (the CLI enables it when stderr is a terminal, or with --progress).
#pragma once

#include <chrono>
#include <string>

namespace kurage::pipeline {

class Progress {
public:
  Progress(std::string label, int total, bool enabled);
  ~Progress();
  void advance(int done);  // items finished so far
  void finish();

private:
  std::string label_;
  int total_;
  bool enabled_;
  bool finished_ = false;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace kurage::pipeline
