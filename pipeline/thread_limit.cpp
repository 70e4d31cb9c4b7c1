#include "pipeline/thread_limit.h"

#include <tbb/global_control.h>

#include <cstddef>

namespace kurage::pipeline {

ThreadLimit::ThreadLimit(int threads) {
  if (threads > 0)
    control_ = new tbb::global_control(tbb::global_control::max_allowed_parallelism, size_t(threads));
}

ThreadLimit::~ThreadLimit() { delete static_cast<tbb::global_control*>(control_); }

int ThreadLimit::current() {
  return int(tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism));
}

}  // namespace kurage::pipeline
