// kurage bench sim: simulation throughput on a running 3-D dam break.
//
// For each particle count (about 100,000 and 250,000 by default), support radius (the paper's
// h = 1.5 l_avr and h = 2 l_avr) and thread count (1 and 2): builds a column of fluid at one
// side of a tank three times its length, lets it collapse for `--warmup` steps (start-up
// excluded), then times `--steps` adaptive steps and reports the mean neighbour count, ms per
// step by step phase and particle-steps per second. `--solver dfsph` (or `all`) adds rows for DFSPH
// at the scene default tolerance (0.1 % mean density error) with boundary-particle walls, h = 2 l
// only (its cubic spline kernel needs the larger support), with its mean iterations per step
// (in all, and by solve); `dfsph-cg` (in `all` too) the same with the divergence solve by
// conjugate gradients, `dfsph-gc` (not in `all`) with fluid.gradient_correction (Bonet & Lok's
// corrected kernel gradient), `dfsph-calm` (not in `all`) with both and the divergence tolerance
// at 0.01 %: the still tank's "calm and corrected" setting, which scenes/jellyfish.json uses;
// `iisph` (in `all` too) as `dfsph` for IISPH. Every row
// also reports simulated seconds per wall second and the measured mean compression. `--cfl` and
// `--pressure-factor` set time_step.cfl and DFSPH's time_step.pressure_factor (0.4 each, as in
// scenes), since the largest step a solver can take is part of its cost; `--warmup-time` warms up
// to a simulated time instead of a step count, and `--duration` times a simulated window instead
// of a step count, so that solvers stepping differently are timed over the same part of the
// collapse; `--max-density-error` sets the incompressible solvers' tolerance, so that each solver
// can be timed at its cheapest setting within a measured compression.
#include "pipeline/commands/cli.h"
#include "pipeline/commands/machine.h"
#include "pipeline/scene_params.h"
#include "sim/simulation.h"

#include <nlohmann/json.hpp>

#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>

namespace kurage::pipeline {

namespace {

// The rows --solver picks: a solver with the settings each row changes, as scene keys of `fluid`
// (the others keep the scenes' defaults).
struct SolverRow {
  const char* name;
  const char* solver;          // fluid.solver
  bool gradientCorrection;     // fluid.gradient_correction
  const char* settings;        // the solver's own keys (sim/solvers/<solver>/), as JSON
};
constexpr std::array<SolverRow, 6> kSolverRows{{{"wcsph", "wcsph", false, "{}"},
                                                {"dfsph", "dfsph", false, "{}"},
                                                {"dfsph-cg", "dfsph", false, R"({"divergence_solve": "cg"})"},
                                                {"dfsph-gc", "dfsph", true, "{}"},
                                                {"dfsph-calm", "dfsph", true, R"({"divergence_solve": "cg", "max_divergence_error": 0.01})"},
                                                {"iisph", "iisph", false, "{}"}}};

const SolverRow* findSolverRow(const std::string& name) {
  for (const SolverRow& row : kSolverRows)
    if (name == row.name) return &row;
  return nullptr;
}

// The step settings of a run (scenes' defaults unless given).
struct StepSettings {
  float soundScale = 1.0f;       // WCSPH's c over 10 sqrt(2 g H)
  float cfl = 0.4f;              // time_step.cfl
  float pressureFactor = 0.4f;   // time_step.pressure_factor (incompressible solvers)
  double warmupTime = -1.0;      // s: warm up to this simulated time instead of `warmup` steps
  float maxDensityError = 0.1f;  // %: fluid.max_density_error, where the solver has it
  float maxDivergenceError = -1.0f;  // %: fluid.max_divergence_error where > 0 and the solver has it (else each row's own)
  double duration = -1.0;        // s: time steps until the clock has advanced this far, instead of `steps` steps
};

sim::SimParams damBreak(int particles, float supportRadius, const std::string& solver, const StepSettings& settings) {
  // Column nx x ny x nz with nz = 1.6 nx, ny = nx.
  const int nx = std::max(2, int(std::round(std::cbrt(particles / 1.6))));
  const int nz = std::max(2, int(std::round(particles / double(nx * nx))));
  sim::SimParams p;
  p.fluid.supportRadius = supportRadius;
  // A liquid, not the paper's gas-like fluid: c = 10 sqrt(2 g H) (docs/design/physics.md), times
  // --sound-speed-scale.
  const float c = settings.soundScale * 10.0f * std::sqrt(2.0f * 6.0f * nz);
  p.fluid.pressureStiffness = c * c;
  p.timeStep.cflFactor = settings.cfl;
  p.timeStep.pressureFactor = settings.pressureFactor;
  p.container.min = Eigen::Vector3f(0, 0, 0);
  p.container.max = Eigen::Vector3f(3.0f * nx, float(nx), 1.2f * nz);
  p.fluidBlocks.push_back({Eigen::Vector3f(0, 0, 0), Eigen::Vector3f(float(nx), float(nx), float(nz))});
  const SolverRow& row = *findSolverRow(solver);
  p.fluid.solver = row.solver;
  p.fluid.gradientCorrection = row.gradientCorrection;
  // The row's settings and the tolerances given, through the solver's own describe()
  nlohmann::json keys = nlohmann::json::parse(row.settings), declared;
  JsonWriter writer(declared);
  describeSolverParams(writer, p.fluid.solver);
  if (declared.contains("max_density_error")) keys["max_density_error"] = settings.maxDensityError;
  if (declared.contains("max_divergence_error") && settings.maxDivergenceError > 0.0f)
    keys["max_divergence_error"] = settings.maxDivergenceError;
  JsonReader reader(keys, "bench sim", "fluid");
  describeSolverParams(reader, p.fluid.solver);
  reader.finish();
  if (sim::makePressureSolver(p.fluid)->incompressible()) {
    p.container.wallDensity = sim::WallDensity::BoundaryParticles;
    p.fluid.pressureForce = sim::PressureForce::Monaghan1992;
  }
  return p;
}

struct BenchRun {
  std::string solver;
  double iterations = 0;         // iterations per step, all of the solver's solves
  std::vector<std::pair<std::string, double>> solveIterations;  // by solve
  double simulatedPerWall = 0;   // simulated seconds per wall-clock second
  double timedFrom = 0;          // simulated time at which the timed steps start, s
  double densityError = 0;       // mean compression over the timed steps (fraction)
  int timedSteps = 0;            // steps timed
  double timedSeconds = 0;       // simulated seconds they covered
  size_t particles = 0;
  float hOverSpacing = 0;
  int threads = 0;
  double meanNeighbours = 0;
  double msPerStep = 0;
  double particleStepsPerSecond = 0;
  double bytesPerParticle = 0;
  std::array<double, size_t(sim::StepPhase::Count)> phaseMs{};
};

BenchRun measure(int particles, float h, int threads, int warmup, int stepCount, const std::string& solver,
                 const StepSettings& settings) {
  ThreadLimit limit(threads);
  sim::Simulation simulation(damBreak(particles, h, solver, settings));
  if (settings.warmupTime >= 0.0)
    while (simulation.time() < settings.warmupTime) simulation.step(simulation.nextStepLimit().step);
  else
    for (int i = 0; i < warmup; ++i) simulation.step(simulation.nextStepLimit().step);
  const sim::SimStats before = simulation.stats();
  const sim::SolverCounters solverBefore = simulation.solver().counters();
  const double timeBefore = simulation.time();
  const auto start = std::chrono::steady_clock::now();
  double neighbours = 0;
  // --duration: the same simulated window for solvers whose steps differ tenfold (its last step
  // may end past it, by less than one step).
  const bool byTime = settings.duration > 0.0;
  int steps = 0;
  while (byTime ? simulation.time() < timeBefore + settings.duration : steps < stepCount) {
    // The adaptive step from the previous step's accelerations (advanceTo recomputes them first;
    // the step size differs negligibly and frames are not needed here).
    simulation.step(simulation.nextStepLimit().step);
    neighbours += double(simulation.neighbors().totalCount()) / simulation.particles().size();
    ++steps;
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  BenchRun r;
  r.solver = solver;
  const sim::SolverCounters after = simulation.solver().counters();
  r.iterations = double(after.iterations() - solverBefore.iterations()) / steps;
  for (size_t k = 0; k < after.solves.size(); ++k)
    r.solveIterations.emplace_back(after.solves[k].name,
                                   double(after.solves[k].iterations - solverBefore.solves[k].iterations) / steps);
  r.simulatedPerWall = (simulation.time() - timeBefore) / seconds;
  r.timedFrom = timeBefore;
  r.timedSteps = steps;
  r.timedSeconds = simulation.time() - timeBefore;
  r.densityError = (simulation.stats().densityErrorSum - before.densityErrorSum) / steps;
  r.particles = simulation.particles().size();
  r.hOverSpacing = h;
  r.threads = threads;
  r.meanNeighbours = neighbours / steps;
  r.msPerStep = 1000.0 * seconds / steps;
  r.particleStepsPerSecond = r.particles * double(steps) / seconds;
  r.bytesPerParticle = double(simulation.memoryBytes()) / r.particles;
  for (size_t s = 0; s < r.phaseMs.size(); ++s)
    r.phaseMs[s] = 1000.0 * (simulation.stats().phaseSeconds[s] - before.phaseSeconds[s]) / steps;
  return r;
}

}  // namespace

int benchSim(ArgParser& args) {
  if (args.flag({"-h", "--help"})) {
    std::printf("usage: kurage bench sim [--particles N]... [--steps N] [--warmup N] [--threads N]\n"
                "                        [--solver wcsph|dfsph|dfsph-cg|dfsph-gc|dfsph-calm|iisph|all]\n"
                "                        [--sound-speed-scale F]\n"
                "                        [--cfl F] [--pressure-factor F] [--warmup-time S]\n"
                "                        [--max-density-error P] [--max-divergence-error P] [--duration S] [--json]\n\n"
                "Times steps of a running 3-D dam break for h = 1.5 and 2 spacings, on 1 and 2 threads\n"
                "(default particle counts 100000 and 250000; --particles may be given once to pick one).\n"
                "--solver dfsph (or all, the default) adds DFSPH rows (h = 2 spacings, boundary particles,\n"
                "0.1 %% mean density error): iterations per step and simulated seconds per wall second;\n"
                "dfsph-cg the same with fluid.divergence_solve \"cg\" (conjugate gradients), dfsph-gc (not in\n"
                "all) with fluid.gradient_correction (the corrected kernel gradient), dfsph-calm (not in all) with\n"
                "both and fluid.max_divergence_error 0.01 (the still tank's calm and corrected setting);\n"
                "iisph (in all) as dfsph for IISPH.\n"
                "--sound-speed-scale F: WCSPH's speed of sound F times the default 10 sqrt(2 g H) (its\n"
                "compression falls as 1/F^2, its step as 1/F; with --warmup 600 the density%% column shows it).\n"
                "--cfl F, --pressure-factor F: time_step.cfl and DFSPH's time_step.pressure_factor (0.4 each).\n"
                "--warmup-time S: warm up to S simulated seconds instead of --warmup steps (the JSON's\n"
                "timed_from_s says where timing began), to time solvers from the same moment.\n"
                "--max-density-error P: fluid.max_density_error in %% (default 0.1) of the solvers that have it,\n"
                "the tolerance on their own predicted error; the density%% column measures every solver's\n"
                "compression alike.\n"
                "--max-divergence-error P: DFSPH's fluid.max_divergence_error in %% for every DFSPH row\n"
                "(default: each row's own, 0.1, or 0.01 for dfsph-calm; the JSON's max_divergence_error_percent\n"
                "is null then).\n"
                "--duration S: time the steps of S simulated seconds instead of --steps (solvers whose steps\n"
                "differ tenfold then cover the same window of the collapse; the JSON's timed_steps and\n"
                "timed_simulated_s say what was timed).\n");
    return 0;
  }
  const bool json = args.flag({"--json"});
  const int steps = args.intOption({"--steps"}, 1, 100000).value_or(30);
  const int warmup = args.intOption({"--warmup"}, 0, 100000).value_or(30);
  std::vector<int> counts{100000, 250000};
  if (auto n = args.intOption({"--particles"}, 8, 100000000)) counts = {*n};
  std::vector<int> threadCounts{1, 2};
  if (auto t = args.intOption({"--threads"}, 1, 1024)) threadCounts = {*t};
  const std::string solverChoice = args.option({"--solver"}).value_or("all");
  const double soundScale = args.doubleOption({"--sound-speed-scale"}).value_or(1.0);
  if (!(soundScale >= 0.1 && soundScale <= 100.0)) args.fail("--sound-speed-scale must be in [0.1, 100]");
  StepSettings settings;
  settings.soundScale = float(soundScale);
  settings.cfl = float(args.doubleOption({"--cfl"}).value_or(0.4));
  if (!(settings.cfl >= 0.01f && settings.cfl <= 2.0f)) args.fail("--cfl must be in [0.01, 2]");
  settings.pressureFactor = float(args.doubleOption({"--pressure-factor"}).value_or(0.4));
  if (!(settings.pressureFactor >= 0.01f && settings.pressureFactor <= 4.0f))
    args.fail("--pressure-factor must be in [0.01, 4]");
  if (auto t = args.doubleOption({"--warmup-time"})) {
    if (!(*t >= 0.0 && *t <= 1000.0)) args.fail("--warmup-time must be in [0, 1000] s");
    settings.warmupTime = *t;
  }
  if (auto d = args.doubleOption({"--duration"})) {
    if (!(*d > 0.0 && *d <= 1000.0)) args.fail("--duration must be in (0, 1000] s");
    settings.duration = *d;
  }
  settings.maxDensityError = float(args.doubleOption({"--max-density-error"}).value_or(0.1));
  if (!(settings.maxDensityError > 0.0f && settings.maxDensityError <= 100.0f))
    args.fail("--max-density-error must be in (0, 100] %");
  if (auto e = args.doubleOption({"--max-divergence-error"})) {
    if (!(*e > 0.0 && *e <= 100.0)) args.fail("--max-divergence-error must be in (0, 100] %");
    settings.maxDivergenceError = float(*e);
  }
  std::vector<std::string> solvers;
  if (solverChoice == "all") solvers = {"wcsph", "dfsph", "dfsph-cg", "iisph"};
  else if (findSolverRow(solverChoice)) solvers = {solverChoice};
  else args.fail("--solver must be wcsph, dfsph, dfsph-cg, dfsph-gc, dfsph-calm, iisph or all");
  if (!args.positionals().empty()) args.fail("unexpected argument");

  nlohmann::json out = {{"benchmark", "sim"}, {"machine", machineRecord()},
                        {"scene", "3-D dam break, column 1 x 1 x 1.6, tank 3 x 1 x 1.2"},
                        {"warmup_steps", warmup},
                        {"timed_steps", settings.duration > 0.0 ? nlohmann::json() : nlohmann::json(steps)},
                        {"sound_speed_scale", soundScale}, {"cfl", settings.cfl},
                        {"pressure_factor", settings.pressureFactor}, {"warmup_time_s", settings.warmupTime},
                        {"duration_s", settings.duration},
                        {"max_density_error_percent", settings.maxDensityError},
                        {"max_divergence_error_percent", settings.maxDivergenceError > 0.0f
                                                             ? nlohmann::json(settings.maxDivergenceError)
                                                             : nlohmann::json()},
                        {"runs", nlohmann::json::array()}};
  if (!json)
    std::printf("%10s %10s %6s %7s %9s %9s %8s %8s %8s %10s %9s %6s %8s %9s\n", "solver", "particles", "h/l", "threads",
                "neighbours", "ms/step", "sort", "density", "forces", "Mpsteps/s", "B/particle", "iters", "sim s/s",
                "density%");
  for (const std::string& solver : solvers)
  for (int count : counts)
    for (float h : {1.5f, 2.0f})
      for (int threads : threadCounts) {
        if (findSolverRow(solver)->solver != std::string("wcsph") && h < 2.0f) continue;
        const BenchRun r = measure(count, h, threads, warmup, steps, solver, settings);
        nlohmann::json phases = nlohmann::json::object();
        for (size_t s = 0; s < r.phaseMs.size(); ++s) phases[std::string(sim::phaseName(sim::StepPhase(s)))] = r.phaseMs[s];
        nlohmann::json bySolve = nlohmann::json::object();
        for (const auto& [name, iterations] : r.solveIterations) bySolve[name] = iterations;
        out["runs"].push_back({{"solver", r.solver}, {"iterations_per_step", r.iterations},
                               {"iterations_per_step_by_solve", bySolve},
                               {"simulated_s_per_wall_s", r.simulatedPerWall}, {"mean_density_error", r.densityError},
                               {"timed_from_s", r.timedFrom}, {"timed_steps", r.timedSteps},
                               {"timed_simulated_s", r.timedSeconds},
                               {"particles", r.particles}, {"h_over_spacing", r.hOverSpacing}, {"threads", r.threads},
                               {"mean_neighbours", r.meanNeighbours}, {"ms_per_step", r.msPerStep},
                               {"ms_per_step_by_phase", phases},
                               {"particle_steps_per_s", r.particleStepsPerSecond},
                               {"bytes_per_particle", r.bytesPerParticle}});
        if (!json) {
          std::printf("%10s %10zu %6.1f %7d %9.1f %9.2f %8.2f %8.2f %8.2f %10.2f %9.0f %6.2f %8.3f %9.3f\n",
                      r.solver.c_str(), r.particles, r.hOverSpacing, r.threads, r.meanNeighbours, r.msPerStep,
                      r.phaseMs[size_t(sim::StepPhase::Sort)], r.phaseMs[size_t(sim::StepPhase::Density)],
                      r.phaseMs[size_t(sim::StepPhase::Forces)], r.particleStepsPerSecond / 1e6, r.bytesPerParticle,
                      r.iterations, r.simulatedPerWall, 100.0 * r.densityError);
          std::fflush(stdout);
        }
      }
  if (json) std::printf("%s\n", out.dump(2).c_str());
  return 0;
}

}  // namespace kurage::pipeline
