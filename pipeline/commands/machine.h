// Where and when a benchmark ran, for its JSON record (`kurage bench ... --json`), so that a
// figure copied into docs/results/performance.md (docs/make_performance.sh) carries its machine,
// date and build: the CPU's model and the instruction-set extensions that matter to the hot loops,
// the cores, the UTC date, and kurage's version and commit (`git describe --always --dirty` at build
// time; "unknown" outside a git checkout). Linux: the CPU is read from /proc/cpuinfo; elsewhere
// its fields are "unknown".
#pragma once

#include <nlohmann/json.hpp>

namespace kurage::pipeline {

// {"cpu_model", "cpu_flags" (those of avx, avx2, fma, avx512f, avx512bw, avx512vl, sse4_2, asimd
// the CPU has), "cores", "date" (ISO 8601, UTC), "kurage_version", "kurage_commit", "build" (the
// build type, and the extensions the binary was compiled to use)}.
nlohmann::json machineRecord();

}  // namespace kurage::pipeline
