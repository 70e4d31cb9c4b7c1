#include "pipeline/commands/machine.h"

#include "kurage_commit.h"  // KURAGE_COMMIT, written at build time (pipeline/commands/commit.cmake)

#include <array>
#include <chrono>
#include <ctime>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <thread>

namespace kurage::pipeline {

namespace {

// The value of the first "KEY : value" line of /proc/cpuinfo, or "".
std::string cpuinfo(const std::string& key) {
  std::ifstream in("/proc/cpuinfo");
  for (std::string line; std::getline(in, line);) {
    if (line.rfind(key, 0) != 0) continue;
    const auto colon = line.find(':');
    if (colon == std::string::npos) continue;
    const auto start = line.find_first_not_of(" \t", colon + 1);
    return start == std::string::npos ? "" : line.substr(start);
  }
  return "";
}

std::string utcNow() {
  const std::time_t now = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  std::tm utc{};
  gmtime_r(&now, &utc);
  std::array<char, 32> text{};
  std::strftime(text.data(), text.size(), "%Y-%m-%dT%H:%M:%SZ", &utc);
  return text.data();
}

// The build type and the extensions the compiler was allowed to use for this binary.
std::string build() {
  std::string out = KURAGE_BUILD_TYPE;
  std::string isa;
#if defined(__AVX512F__)
  isa += " avx512f";
#endif
#if defined(__AVX2__)
  isa += " avx2";
#endif
#if defined(__FMA__)
  isa += " fma";
#endif
  out += isa.empty() ? ", baseline instruction set" : ", compiled for" + isa;
  return out;
}

}  // namespace

nlohmann::json machineRecord() {
  std::string model = cpuinfo("model name");
  if (model.empty()) model = "unknown";
  std::istringstream flagList(cpuinfo("flags") + " " + cpuinfo("Features"));  // x86, aarch64
  std::set<std::string> present;
  for (std::string f; flagList >> f;) present.insert(f);
  nlohmann::json flags = nlohmann::json::array();
  for (const char* f : {"sse4_2", "avx", "avx2", "fma", "avx512f", "avx512bw", "avx512vl", "asimd"})
    if (present.count(f)) flags.push_back(f);
  return {{"cpu_model", model},
          {"cpu_flags", flags},
          {"cores", std::thread::hardware_concurrency()},
          {"date", utcNow()},
          {"kurage_version", KURAGE_VERSION},
          {"kurage_commit", KURAGE_COMMIT},
          {"build", build()}};
}

}  // namespace kurage::pipeline
