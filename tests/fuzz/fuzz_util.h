// Shared by the libFuzzer targets (tests/fuzz/README.md): each input is written to a file in a
// scratch folder private to the process, read by the real reader, and the only acceptable
// outcomes are a result or the reader's documented error naming the file. Anything else, an
// exception of another type, an error that does not name the file, or a sanitizer report, is a
// finding: the target aborts.
#pragma once

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <string>

namespace kurage::fuzz {

// A scratch folder for this process, removed at exit. KURAGE_SOURCE_DIR (compile definition)
// names the source tree, from which a target may copy what its inputs refer to.
inline const std::filesystem::path& scratch() {
  static const std::filesystem::path dir = [] {
    std::filesystem::path d = std::filesystem::temp_directory_path() / ("kurage-fuzz-" + std::to_string(::getpid()));
    std::filesystem::create_directories(d);
    std::atexit([] {
      std::error_code ignored;
      std::filesystem::remove_all(scratch(), ignored);
    });
    return d;
  }();
  return dir;
}

inline void writeInput(const std::filesystem::path& file, const uint8_t* data, size_t size) {
  std::ofstream out(file, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(data), std::streamsize(size));
  if (!out) {
    std::fprintf(stderr, "fuzz: cannot write %s\n", file.c_str());
    std::abort();
  }
}

// The reader's error must name the file it read; otherwise the target fails.
inline void requireNamesFile(const std::exception& e, const std::filesystem::path& file) {
  if (std::string(e.what()).find(file.filename().string()) == std::string::npos) {
    std::fprintf(stderr, "fuzz: an error that does not name the file %s: %s\n", file.c_str(), e.what());
    std::abort();
  }
}

}  // namespace kurage::fuzz
