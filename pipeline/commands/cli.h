// The kurage command line: a small argument parser shared by the commands, and one function per
// command, each in its own pipeline/commands/cmd_*.cpp. These files make the `kurage` executable
// and nothing else; the libraries (pipeline/, pipeline/analysis/, pipeline/io/) never include
// them. Commands report errors by throwing; only main() turns them into exit codes (2 for
// UsageError and SceneError, 1 for anything else).
#pragma once

#include "pipeline/io/run_lock.h"
#include "pipeline/stages.h"
#include "pipeline/thread_limit.h"

#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace kurage::pipeline {

class UsageError : public std::runtime_error {
public:
  using std::runtime_error::runtime_error;
};

// Consumes options from a command's arguments; whatever is left must be positional.
class ArgParser {
public:
  ArgParser(std::string command, std::vector<std::string> args) : command_(std::move(command)), args_(std::move(args)) {}

  bool flag(std::initializer_list<const char*> names);
  std::optional<std::string> option(std::initializer_list<const char*> names);
  // Every value of a repeatable option, in the order given (all are consumed).
  std::vector<std::string> options(std::initializer_list<const char*> names);
  std::optional<int> intOption(std::initializer_list<const char*> names, int min, int max);
  std::optional<double> doubleOption(std::initializer_list<const char*> names);
  // The remaining arguments; throws UsageError for any leftover "-..." option.
  std::vector<std::string> positionals();
  [[noreturn]] void fail(const std::string& message) const;

private:
  std::string command_;
  std::vector<std::string> args_;
};

// Options every stage command shares: -o OUT, --frames A-B, --threads N, --progress.
struct StageCommandOptions {
  StageOptions stage;
  int threads = 0;  // 0: all cores
};
StageCommandOptions parseStageOptions(ArgParser& args, bool requireOutput);
// frameRange(), its error a command-line error (exit 2).
std::pair<int, int> checkedFrameRange(const ArgParser& args, const Scene& scene, const StageOptions& options);
extern const char* const kStageOptionsHelp;

// What every command that writes into OUT does before writing: takes OUT's run lock, held until
// the object dies (not for a farm task, `task` not empty: see cmd_stage.cpp), removes the
// temporaries a killed run left, and installs the SIGINT/SIGTERM handlers (pipeline/interrupt.h).
class ClaimedOutput {
public:
  ClaimedOutput(const std::filesystem::path& outDir, const std::string& command, const std::string& task = "");

private:
  std::optional<RunLock> lock_;
};

// --quality preview|final (default final: the scene as written).
Quality parseQuality(ArgParser& args);
extern const char* const kQualityHelp;

// Commands. `args` excludes the program and command names.
int commandStage(const std::string& name, std::vector<std::string> args);  // run, sim, surface, render
int commandCheck(std::vector<std::string> args);
int commandSchema(std::vector<std::string> args);
int commandBench(std::vector<std::string> args);  // dispatches to the bench* functions below
int commandStill(std::vector<std::string> args);  // pipeline/commands/cmd_still.cpp
int commandPreview(std::vector<std::string> args);  // pipeline/commands/cmd_preview.cpp
int commandExport(std::vector<std::string> args);   // pipeline/commands/cmd_export.cpp
int benchSim(ArgParser& args);      // pipeline/commands/cmd_bench_sim.cpp
int benchRender(ArgParser& args);   // pipeline/commands/cmd_bench_render.cpp
int benchSurface(ArgParser& args);  // pipeline/commands/cmd_bench_surface.cpp
int commandFarm(std::vector<std::string> args);   // pipeline/commands/cmd_farm.cpp
int commandStudy(std::vector<std::string> args);  // pipeline/commands/cmd_study.cpp
int commandReport(std::vector<std::string> args);  // pipeline/commands/cmd_report.cpp
int commandFigures(std::vector<std::string> args);  // pipeline/commands/cmd_figures.cpp

}  // namespace kurage::pipeline
