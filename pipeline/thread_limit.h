// How many worker threads TBB may use while an object lives: the commands' --threads and a
// study's runs (pipeline/studies/study.h). A limit of 0 leaves TBB's default (all cores).
// Limits nest as tbb::global_control does: the smallest one alive applies.
#pragma once

namespace kurage::pipeline {

class ThreadLimit {
public:
  explicit ThreadLimit(int threads);
  ~ThreadLimit();
  ThreadLimit(const ThreadLimit&) = delete;
  ThreadLimit& operator=(const ThreadLimit&) = delete;
  // The parallelism in effect now.
  static int current();

private:
  void* control_ = nullptr;
};

}  // namespace kurage::pipeline
