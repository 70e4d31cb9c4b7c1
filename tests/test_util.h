// Helpers shared by the tests: a fresh temporary folder per test, and running the CLI.
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <random>
#include <stdexcept>
#include <fcntl.h>
#include <string>
#include <sys/wait.h>
#include <unistd.h>
#include <vector>

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

// How startKurage starts the child: variables set in its environment, and whether it leads a
// process group of its own (so that a test can signal the group, as Ctrl-C in a terminal does).
struct StartOptions {
  std::vector<std::pair<std::string, std::string>> environment;
  bool ownProcessGroup = false;
};

// Starts build/kurage with the given arguments in a child process, stdout and stderr appended
// to `log`; returns its pid (for tests that signal it).
inline pid_t startKurage(const std::vector<std::string>& args, const std::filesystem::path& log,
                         const StartOptions& options = {}) {
  const std::string kurage = (binaryDir() / "kurage").string();
  const pid_t pid = ::fork();
  if (pid == 0) {
    if (options.ownProcessGroup) ::setpgid(0, 0);
    for (const auto& [name, value] : options.environment) ::setenv(name.c_str(), value.c_str(), 1);
    const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
    ::dup2(fd, 1);
    ::dup2(fd, 2);
    std::vector<char*> argv{const_cast<char*>(kurage.c_str())};
    for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    ::execv(kurage.c_str(), argv.data());
    ::_exit(127);
  }
  return pid;
}

// Waits for a child: its exit code, or 128 + the signal that killed it.
inline int waitFor(pid_t pid) {
  int status = 0;
  ::waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

// The temporaries (".NAME.PID.N.tmp") under `folder`.
inline std::vector<std::filesystem::path> temporariesIn(const std::filesystem::path& folder) {
  std::vector<std::filesystem::path> found;
  if (!std::filesystem::exists(folder)) return found;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(folder))
    if (entry.path().extension() == ".tmp") found.push_back(entry.path());
  return found;
}

// Expects `call` to throw std::runtime_error whose message names `path` (and contains `detail`).
template <typename Call>
void expectErrorNamingPath(Call call, const std::filesystem::path& path, const std::string& detail = "") {
  try {
    call();
    ADD_FAILURE() << "no exception for " << path;
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(path.string()), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(detail), std::string::npos) << e.what();
  }
}

}  // namespace kurage::test
