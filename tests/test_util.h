// Helpers shared by the tests: a fresh temporary folder per test, and running the CLI.
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <random>
#include <sys/wait.h>
#include <string>

namespace kurage::test {

// A new empty folder under the system temporary directory, removed when the object dies
// (kept when KURAGE_KEEP_TEST_OUTPUT is set, for debugging).
class TempDir {
public:
  TempDir() {
    std::random_device rd;
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    std::string name = "kurage-test-";
    if (info) name += std::string(info->test_suite_name()) + "-" + info->name() + "-";
    for (char& c : name)
      if (c == '/') c = '_';
    path_ = std::filesystem::temp_directory_path() / (name + std::to_string(rd()));
    std::filesystem::create_directories(path_);
  }
  ~TempDir() {
    if (!std::getenv("KURAGE_KEEP_TEST_OUTPUT")) {
      std::error_code ignored;
      std::filesystem::remove_all(path_, ignored);
    }
  }
  const std::filesystem::path& path() const { return path_; }

private:
  std::filesystem::path path_;
};

inline std::filesystem::path sourceDir() { return KURAGE_SOURCE_DIR; }
inline std::filesystem::path binaryDir() { return KURAGE_BINARY_DIR; }

// Runs build/kurage with the given arguments, stdout and stderr into `log`; returns the exit code.
inline int runKurage(const std::string& arguments, const std::filesystem::path& log) {
  const std::string command = (binaryDir() / "kurage").string() + " " + arguments + " > " + log.string() + " 2>&1";
  const int status = std::system(command.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace kurage::test
