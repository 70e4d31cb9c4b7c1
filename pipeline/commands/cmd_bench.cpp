// kurage bench sim | render | surface
#include "pipeline/commands/cli.h"

#include <cstdio>

namespace kurage::pipeline {

int commandBench(std::vector<std::string> rawArgs) {
  if (rawArgs.empty() || rawArgs[0] == "-h" || rawArgs[0] == "--help") {
    std::printf("usage: kurage bench sim|render|surface [options] [--json]\n\n"
                "Prints performance figures; `kurage bench WHAT --help` lists the options of each.\n");
    return 0;
  }
  const std::string what = rawArgs[0];
  ArgParser args("bench " + what, std::vector<std::string>(rawArgs.begin() + 1, rawArgs.end()));
  if (what == "sim") return benchSim(args);
  if (what == "render") return benchRender(args);
  if (what == "surface") return benchSurface(args);
  throw UsageError("bench: unknown benchmark " + what + " (sim, render, surface)");
}

}  // namespace kurage::pipeline
