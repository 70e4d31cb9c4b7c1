// Once running, the step loop allocates nothing (issue 3): every per-step buffer keeps its
// capacity. This executable counts calls to the global operator new.
#include "sim/simulation.h"

#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <new>

namespace {
std::atomic<long> allocations{0};
}

// The replacements pair malloc with free; GCC at the tests' -O1 (CMakeLists.txt) inlines the
// replaced operator new into callers and reads the free as mismatched with it.
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
void* operator new(std::size_t size) {
  allocations.fetch_add(1, std::memory_order_relaxed);
  if (void* p = std::malloc(size ? size : 1)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }

using namespace kurage::sim;

TEST(StepLoop, AllocatesNothingOnceRunning) {
  SimParams p;
  p.fluid.pressureStiffness = 400.0f;
  p.container.max = Eigen::Vector3f(24, 8, 12);
  p.fluidBlocks.push_back({Eigen::Vector3f(0, 0, 0), Eigen::Vector3f(8, 8, 10)});
  p.container.wallDensity = WallDensity::WallWeight;
  Simulation sim(p);
  sim.advanceTo(0.5);  // warm up: buffers reach their working sizes
  const long before = allocations.load();
  ASSERT_GT(before, 0) << "the counting operator new is not in use";
  sim.advanceTo(1.0);
  const uint64_t steps = sim.stats().steps;
  EXPECT_GT(steps, 10u);
  // TBB may allocate task objects internally; our own code must not allocate per step. Allow a
  // small constant, far below one allocation per step.
  EXPECT_LT(allocations.load() - before, 5) << "allocations during " << steps << " steps";
}
