// kurage report OUT: OUT/report.html for an existing run (pipeline/report/run_report.h).
#include "pipeline/commands/cli.h"
#include "pipeline/report/run_report.h"

#include <cstdio>

namespace kurage::pipeline {

int commandReport(std::vector<std::string> rawArgs) {
  ArgParser args("report", std::move(rawArgs));
  if (args.flag({"-h", "--help"})) {
    std::printf(
        "usage: kurage report OUT\n\n"
        "Writes OUT/report.html, the run in OUT as one page that opens from disk with no network: its\n"
        "status, warnings and cap hits at the top, the film and a contact sheet of frames, the scene in\n"
        "brief with the command and versions, where the time went, the simulation per frame\n"
        "(OUT/sim_frames.csv: step size, solver iterations, density error, particles, kinetic energy)\n"
        "and the bodies per frame (OUT/bodies.csv), and the outputs with what opens each. `kurage run`,\n"
        "each stage command and `kurage farm merge` write it themselves, kept current while they run;\n"
        "this command redraws it from what OUT holds (a run from an older kurage, a copied folder).\n\n"
        "Exit status: 0 when the page was written; 1 when OUT is not a run (no OUT/run.json), its\n"
        "run.json, sim_frames.csv or bodies.csv is damaged (the message names the file), or the page\n"
        "cannot be written; then any page already there is left as it was. 2 for a usage error.\n\n"
        "  -h, --help         this help\n");
    return 0;
  }
  const std::vector<std::string> positional = args.positionals();
  if (positional.size() != 1) args.fail("expected one OUT folder");
  writeRunReport(positional[0]);
  std::printf("report: %s\n", (std::filesystem::path(positional[0]) / "report.html").string().c_str());
  return 0;
}

}  // namespace kurage::pipeline
