// kurage figures DIR: every figure of the paper from its three experiments (pipeline/figures/).
#include "pipeline/commands/cli.h"
#include "pipeline/figures/figures.h"
#include "pipeline/interrupt.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <sstream>

namespace kurage::pipeline {

namespace {

constexpr const char* kHelp =
    "usage: kurage figures DIR [--quality tiny|preview|final] [--only FIG] [--scenes SCENES] [--threads N]\n\n"
    "Runs the paper's three experiments, each only as far as its figure needs, and writes its figures\n"
    "in the paper's layout into DIR (created if missing):\n"
    "  fig2_membrane.png   Fig. 2: fluid poured onto the pinned membrane at three moments (columns):\n"
    "                      the telescopic model (top), its cross-section (middle), the conventional\n"
    "                      mass-spring model leaking (bottom); membrane.json, membrane_conventional.json\n"
    "  fig3_box.png        Fig. 3: the box floating, contracted and sunk, released and rising, swollen,\n"
    "                      floating again, above the applied force against time; box.json\n"
    "  fig5_jellyfish.png  Fig. 5: six frames over one pulse cycle while the right faucet pours, above\n"
    "                      the ring muscle's force over that cycle; jellyfish.json\n"
    "  fig3_force.*, fig5_force.*  the plots alone: PNG, SVG, PDF and the gnuplot script\n"
    "  figures.json        each figure's scenes, moments, camera and wall time\n\n"
    "options:\n"
    "  --quality Q        preview (default: the scenes' preview quality, small stills; minutes on\n"
    "                     2 cores), final (the scenes as written, large stills, for print) or tiny\n"
    "                     (thumbnails of the first half second, seconds; for tests)\n"
    "  --only FIG         fig2, fig3 or fig5 (repeatable); default: all three\n"
    "  --scenes SCENES    the folder of the paper's scenes (default: scenes)\n"
    "  --threads N        worker threads (default: all cores)\n"
    "  --quiet            no line per step on stderr\n"
    "  -h, --help         this help\n";

}  // namespace

int commandFigures(std::vector<std::string> rawArgs) {
  ArgParser args("figures", std::move(rawArgs));
  if (args.flag({"-h", "--help"})) {
    std::fputs(kHelp, stdout);
    return 0;
  }
  FigureOptions options;
  if (const std::optional<std::string> q = args.option({"--quality"})) {
    try {
      options.quality = parseFigureQuality(*q);
    } catch (const std::invalid_argument& e) {
      args.fail(std::string("--quality: ") + e.what());
    }
  }
  options.only = args.options({"--only"});
  for (const std::string& name : options.only)
    if (std::find(figureNames().begin(), figureNames().end(), name) == figureNames().end())
      args.fail("--only: expected fig2, fig3 or fig5, got " + name);
  if (const std::optional<std::string> scenes = args.option({"--scenes"})) options.scenesDir = *scenes;
  const std::optional<int> threadCount = args.intOption({"--threads"}, 1, 1024);
  const bool quiet = args.flag({"--quiet"});
  const std::vector<std::string> positional = args.positionals();
  if (positional.size() != 1) args.fail("expected one output folder DIR");
  options.outDir = positional[0];
  if (!std::filesystem::is_directory(options.scenesDir))
    args.fail("--scenes: folder " + options.scenesDir.string() + " does not exist (run from the repository root)");
  if (!quiet) options.log = [](const std::string& line) { std::fprintf(stderr, "%s\n", line.c_str()); };

  installInterruptHandlers();
  ThreadLimit threads(threadCount.value_or(0));
  const auto start = std::chrono::steady_clock::now();
  const std::vector<std::filesystem::path> files = writeFigures(options);
  for (const std::filesystem::path& f : files) std::printf("figure: %s\n", f.string().c_str());
  std::printf("figures: %s (%s, %.0f s)\n", options.outDir.string().c_str(), figureQualityName(options.quality),
              std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  return 0;
}

}  // namespace kurage::pipeline
