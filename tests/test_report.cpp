// The report pages (label `unit`): the SVG plotter draws every point it is given where it
// belongs, the per-frame records of the simulation add up to the run's totals and survive a
// checkpoint, and OUT/report.html shows what OUT holds (warnings only where there are some, a
// failed or stopped run as such, a running one refreshing until it ends), escapes what it quotes,
// and refuses a folder that is not a run or a damaged record without touching the page there.
// tests/test_report_browser.cpp opens the pages in Chromium.
#include "pipeline/analysis/sim_series.h"
#include "pipeline/io/csv.h"
#include "pipeline/io/files.h"
#include "pipeline/io/run_lock.h"
#include "pipeline/report/html.h"
#include "pipeline/report/run_report.h"
#include "pipeline/report/study_report.h"
#include "pipeline/report/svg_plot.h"
#include "pipeline/scene.h"
#include "sim/simulation.h"

#include "test_util.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <regex>

namespace kurage::pipeline {
namespace {

namespace fs = std::filesystem;
using test::TempDir;

// The text of the element <svg ... id="ID"> ... </svg>.
std::string svgById(const std::string& html, const std::string& id) {
  const size_t at = html.find("id=\"" + id + "\"");
  if (at == std::string::npos) return "";
  const size_t start = html.rfind("<svg", at);
  return html.substr(start, html.find("</svg>", at) + 6 - start);
}

// The <g class="series"> of `label` in an SVG.
std::string seriesOf(const std::string& svg, const std::string& label) {
  const size_t at = svg.find("<g class=\"series\" data-label=\"" + label + "\"");
  if (at == std::string::npos) return "";
  return svg.substr(at, svg.find("</g>", at) - at);
}

struct Vertex {
  double x, y;
};
// Every vertex of every polyline in `svg`, one list per polyline.
std::vector<std::vector<Vertex>> polylines(const std::string& svg) {
  std::vector<std::vector<Vertex>> lines;
  const std::regex points("<polyline[^>]* points=\"([^\"]*)\"");
  for (auto it = std::sregex_iterator(svg.begin(), svg.end(), points); it != std::sregex_iterator(); ++it) {
    std::vector<Vertex> line;
    std::istringstream in((*it)[1].str());
    std::string pair;
    while (in >> pair) line.push_back({std::stod(pair.substr(0, pair.find(','))), std::stod(pair.substr(pair.find(',') + 1))});
    lines.push_back(line);
  }
  return lines;
}

size_t vertexCount(const std::string& svg) {
  size_t n = 0;
  for (const auto& line : polylines(svg)) n += line.size();
  return n;
}

size_t count(const std::string& text, const std::string& what) {
  size_t n = 0;
  for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

// ---- The SVG plotter ----

TEST(SvgPlot, NiceTicksCoverTheRangeInStepsOfOneTwoOrFive) {
  const struct {
    double lo, hi;
    int count;
  } cases[] = {{0, 1, 5}, {0.013, 0.017, 5}, {-3, 7, 4}, {369, 371, 5}, {2e-6, 9e-5, 6}, {0, 1.4e6, 5}};
  for (const auto& c : cases) {
    SCOPED_TRACE(std::to_string(c.lo) + " .. " + std::to_string(c.hi));
    const std::vector<double> t = niceTicks(c.lo, c.hi, c.count);
    ASSERT_GE(t.size(), 2u);
    const double step = t[1] - t[0];
    EXPECT_LE(t.front(), c.lo + 1e-9 * step);
    EXPECT_GE(t.back(), c.hi - 1e-9 * step);
    EXPECT_LT(t.size(), size_t(3 * c.count)) << "far more ticks than asked for";
    const double mantissa = step / std::pow(10.0, std::floor(std::log10(step) + 1e-9));
    EXPECT_TRUE(std::fabs(mantissa - 1) < 1e-6 || std::fabs(mantissa - 2) < 1e-6 || std::fabs(mantissa - 5) < 1e-6)
        << step;
    for (size_t i = 1; i < t.size(); ++i) EXPECT_NEAR(t[i] - t[i - 1], step, 1e-9 * step);
  }
}

TEST(SvgPlot, TickLabelsUseTheFewestDigitsThatTellTicksApart) {
  EXPECT_EQ(tickLabel(0.015, 0.001, 0.02), "0.015");
  EXPECT_EQ(tickLabel(150, 50, 200), "150");
  EXPECT_EQ(tickLabel(370.5, 0.5, 371), "370.5");
  EXPECT_EQ(tickLabel(1.5e6, 5e5, 1.5e6), "1.5e6");
  EXPECT_EQ(tickLabel(5e5, 5e5, 1.5e6), "5e5");  // as its axis's largest tick
  EXPECT_EQ(tickLabel(2e-5, 1e-5, 3e-5), "2e-5");
  EXPECT_EQ(tickLabel(1e-17, 0.2, 1.0), "0");
}

Plot linePlot(std::vector<double> y, bool log = false) {
  Plot plot;
  plot.title = "test";
  plot.x.label = "time (s)";
  plot.y.label = "value";
  plot.y.log = log;
  PlotSeries s;
  s.label = "values";
  for (size_t i = 0; i < y.size(); ++i) s.x.push_back(double(i));
  s.y = std::move(y);
  plot.series.push_back(s);
  return plot;
}

TEST(SvgPlot, EveryFinitePointIsAVertexOfOneLineAndAGapBreaksIt) {
  const double nan = std::nan("");
  const std::string svg = svgPlot(linePlot({0, 1, 4, 9, nan, 25, 36, 49, 64, 81}), "p");
  const auto lines = polylines(seriesOf(svg, "values"));
  ASSERT_EQ(lines.size(), 2u) << svg;
  EXPECT_EQ(lines[0].size(), 4u);
  EXPECT_EQ(lines[1].size(), 5u);
}

TEST(SvgPlot, PointsLieInThePlotAreaInTheOrderOfTheirValues) {
  const Plot plot = linePlot({3, -1, 7, 2});
  const std::string svg = svgPlot(plot, "p");
  const auto lines = polylines(svg);
  ASSERT_EQ(lines.size(), 1u);
  const std::vector<Vertex>& v = lines[0];
  ASSERT_EQ(v.size(), 4u);
  for (const Vertex& p : v) {
    EXPECT_GT(p.x, 0.0);
    EXPECT_LT(p.x, plot.width);
    EXPECT_GT(p.y, 0.0);
    EXPECT_LT(p.y, plot.height);
  }
  for (size_t i = 1; i < v.size(); ++i) EXPECT_GT(v[i].x, v[i - 1].x);  // x grows to the right
  EXPECT_LT(v[2].y, v[0].y);  // 7 above 3: y grows upwards
  EXPECT_LT(v[0].y, v[3].y);
  EXPECT_LT(v[3].y, v[1].y);
  // Equal steps in value are equal steps in pixels (linear axis): (3 - 2) vs (2 - (-1)).
  EXPECT_NEAR((v[3].y - v[0].y) * 3.0, v[1].y - v[3].y, 0.2);
}

TEST(SvgPlot, ALogAxisSkipsValuesThatAreNotPositive) {
  const std::string svg = seriesOf(svgPlot(linePlot({1, 0, -1, 10, 100}, true), "p"), "values");
  const auto lines = polylines(svg);
  ASSERT_EQ(lines.size(), 2u) << svg;
  EXPECT_EQ(lines[0].size(), 1u);
  EXPECT_EQ(lines[1].size(), 2u);
  EXPECT_EQ(count(svg, "<circle"), 1u) << "a point alone on its line gets a marker";
  // A decade is a decade: 1 -> 10 and 10 -> 100 are as far apart.
  EXPECT_NEAR(lines[0][0].y - lines[1][0].y, lines[1][0].y - lines[1][1].y, 0.2);
}

TEST(SvgPlot, TextIsEscaped) {
  Plot plot = linePlot({1, 2});
  plot.title = "<script>alert(1)</script> & co";
  plot.series[0].label = "a \"quoted\" <b>";
  const std::string svg = svgPlot(plot, "p");
  EXPECT_EQ(svg.find("<script"), std::string::npos);
  EXPECT_EQ(svg.find("<b>"), std::string::npos);
  EXPECT_NE(svg.find("&lt;script&gt;alert(1)&lt;/script&gt; &amp; co"), std::string::npos);
  EXPECT_NE(svg.find("data-label=\"a &quot;quoted&quot; &lt;b&gt;\""), std::string::npos);
}

TEST(SvgPlot, BarsAreAsLongAsTheirValues) {
  const std::string svg = svgBarChart("t", {{"a", 1.0, "1 s"}, {"b", 3.0, "3 s"}, {"c", 0.0, "0 s"}}, "b");
  const std::regex bar("class=\"bar\" data-value=\"([^\"]*)\"[^>]* width=\"([^\"]*)\"");
  std::vector<double> widths;
  for (auto it = std::sregex_iterator(svg.begin(), svg.end(), bar); it != std::sregex_iterator(); ++it)
    widths.push_back(std::stod((*it)[2].str()));
  ASSERT_EQ(widths.size(), 3u) << svg;
  EXPECT_NEAR(widths[1] / widths[0], 3.0, 0.02);
  EXPECT_LE(widths[2], 1.0);
}

TEST(Html, EscapesTextAndLinksNamesThatNeedIt) {
  EXPECT_EQ(escapeHtml("<a href='x'>&\""), "&lt;a href=&#39;x&#39;&gt;&amp;&quot;");
  EXPECT_EQ(urlPath("frames/0001.png"), "frames/0001.png");
  EXPECT_EQ(urlPath("my film #1?.mp4"), "my%20film%20%231%3F.mp4");
  EXPECT_EQ(formatDuration(0.42), "0.42 s");
  EXPECT_EQ(formatDuration(12.34), "12.3 s");
  EXPECT_EQ(formatDuration(245), "4 min 05 s");
  EXPECT_EQ(formatDuration(7620), "2 h 07 min");
  EXPECT_EQ(formatDuration(2.2e-5), "22 µs");
  EXPECT_EQ(formatNumber(1.5e-5), "1.5e-5");
}

// ---- The simulation's per-frame records ----

Scene tinyJellyfish(const std::string& solver) {
  nlohmann::json doc = nlohmann::json::parse(readText(test::sourceDir() / "tests/scenes/tiny_jellyfish.json"));
  doc.erase("$schema");
  if (solver != "wcsph") {
    doc["fluid"].erase("pressure_stiffness");
    doc["fluid"].erase("pressure_force");
    doc["fluid"]["solver"] = solver;
  }
  return parseScene(doc, "tiny_jellyfish.json");
}

TEST(SimSeries, FramesAddUpToTheRunAndSurviveACheckpoint) {
  for (const char* solver : {"wcsph", "dfsph"}) {
    SCOPED_TRACE(solver);
    const Scene scene = tinyJellyfish(solver);
    sim::Simulation simulation(scene.sim);
    SimSeries series(simulation, scene.output.frameCount());
    for (int f = 0; f < 4; ++f) {
      simulation.advanceTo(scene.output.frameTime(f));
      series.record(simulation);
    }
    const CsvTable t = parseCsvTable(series.csv(), "sim_frames.csv");
    ASSERT_EQ(t.rows.size(), 4u);
    EXPECT_TRUE(t.has("collision_cap_hits"));  // the scene has bodies
    const std::vector<double> steps = t.numbers("steps"), step = t.numbers("mean_step_s"), time = t.numbers("time_s");
    double total = 0.0;
    for (size_t f = 0; f < steps.size(); ++f) total += steps[f];
    EXPECT_EQ(total, double(simulation.stats().steps));
    EXPECT_TRUE(std::isnan(step[0]));  // frame 0 has no steps
    for (size_t f = 1; f < 4; ++f) EXPECT_NEAR(step[f] * steps[f], time[f] - time[f - 1], 1e-9);
    EXPECT_EQ(t.numbers("particles").back(), double(simulation.particles().size()));
    EXPECT_NEAR(t.numbers("kinetic_energy_J").back(), sim::kineticEnergy(simulation.particles()),
                1e-8 * sim::kineticEnergy(simulation.particles()));
    if (std::string(solver) == "dfsph") {
      const std::vector<double> perStep = t.numbers("density_iterations_per_step");
      double iterations = 0.0;
      for (size_t f = 1; f < 4; ++f) iterations += perStep[f] * steps[f];
      EXPECT_NEAR(iterations, double(simulation.solver().counters().solves.at(0).iterations), 1e-6);
      EXPECT_TRUE(t.has("divergence_cap_hits"));
    } else {
      EXPECT_FALSE(t.has("density_iterations_per_step"));  // WCSPH has no iterations
    }
    SimSeries restored(simulation, scene.output.frameCount());
    restored.restoreState(series.saveState());
    EXPECT_EQ(restored.csv(), series.csv());
    SimSeries small(simulation, 2);  // more rows than frames: damage
    EXPECT_THROW(small.restoreState(series.saveState()), sim::StateError);
    EXPECT_THROW(restored.restoreState(series.saveState() + "x"), sim::StateError);
  }
}

// ---- The run's page ----

// An OUT with a run.json of `status` and, where given, warnings of the simulation.
fs::path fakeRun(const fs::path& dir, const std::string& status, nlohmann::json warnings = nlohmann::json::array()) {
  const fs::path out = dir / "out";
  fs::create_directories(out);
  nlohmann::json run = {
      {"status", status},
      {"command_line", "kurage run demo.json -o out"},
      {"scene_file", "demo.json"},
      {"parameters",
       {{"name", "demo"},
        {"description", "A <b>bold</b> scene & more"},
        {"output", {{"fps", 6}, {"duration", 1.0}}},
        {"fluid", {{"solver", "dfsph"}, {"max_density_error", 0.1}, {"max_iterations", 100}}},
        {"bodies", {{{"name", "bell"}, {"shape", "shell"}, {"muscles", {{{"name", "ring"}}}}}}}}},
      {"derived", {{"frame_count", 7}}},
      {"stages", {{"sim", {{"seconds", 1.5}, {"steps", 60}, {"warnings", warnings}}}, {"render", {{"seconds", 4.5}}}}}};
  writeTextAtomic(out / "run.json", run.dump(2));
  return out;
}

TEST(RunReport, AWarningsBoxOnlyWhereThereAreWarnings) {
  TempDir dir;
  const fs::path clean = fakeRun(dir.path() / "clean", "complete");
  EXPECT_EQ(runReportHtml(clean).find("id=\"warnings\""), std::string::npos);
  const fs::path capped = fakeRun(dir.path() / "capped", "complete",
                                  {{{"message", "the dfsph solver stopped at its iteration cap in 12 density solves"},
                                    {"key", "stages.sim.solver"}}});
  const std::string page = runReportHtml(capped);
  EXPECT_NE(page.find("id=\"warnings\""), std::string::npos);
  EXPECT_NE(page.find("stopped at its iteration cap in 12 density solves"), std::string::npos);
  EXPECT_NE(page.find("<code>stages.sim.solver</code>"), std::string::npos);
}

TEST(RunReport, AFailedRunShowsItsError) {
  TempDir dir;
  const fs::path out = fakeRun(dir.path(), "failed");
  nlohmann::json run = nlohmann::json::parse(readText(out / "run.json"));
  run["error"] = "simulation stopped: a non-finite velocity";
  writeTextAtomic(out / "run.json", run.dump());
  const std::string page = runReportHtml(out);
  EXPECT_NE(page.find("class=\"warnings error\""), std::string::npos);
  EXPECT_NE(page.find("a non-finite velocity"), std::string::npos);
  EXPECT_NE(page.find("class=\"status failed\""), std::string::npos);
}

TEST(RunReport, ARunningRecordWithoutItsProcessIsAStoppedRun) {
  TempDir dir;
  const fs::path out = fakeRun(dir.path(), "running");
  std::string page = runReportHtml(out);
  EXPECT_NE(page.find("class=\"status stopped\""), std::string::npos);
  EXPECT_NE(page.find("no process holds the folder&#39;s lock"), std::string::npos);
  EXPECT_EQ(page.find("http-equiv=\"refresh\""), std::string::npos);
  const RunLock lock(out, "test");  // a run holds OUT: the page follows it
  page = runReportHtml(out);
  EXPECT_NE(page.find("class=\"status running\""), std::string::npos);
  EXPECT_NE(page.find("http-equiv=\"refresh\""), std::string::npos);
}

TEST(RunReport, TextFromTheRunIsEscaped) {
  TempDir dir;
  const std::string page = runReportHtml(fakeRun(dir.path(), "complete"));
  EXPECT_EQ(page.find("<b>bold</b>"), std::string::npos);
  EXPECT_NE(page.find("A &lt;b&gt;bold&lt;/b&gt; scene &amp; more"), std::string::npos);
}

TEST(RunReport, ThePlotsHoldEveryValueOfTheRecords) {
  TempDir dir;
  const fs::path out = fakeRun(dir.path(), "complete");
  writeTextAtomic(out / "sim_frames.csv",
                  "frame,time_s,steps,mean_step_s,step_bound,mean_density_error,density_iterations_per_step,"
                  "density_cap_hits,particles,kinetic_energy_J\n"
                  "0,0,0,,,,,0,100,0\n1,0.1667,5,0.0333,cfl,0.001,3,0,100,10\n2,0.3333,5,0.0333,cfl,0.002,4,2,101,20\n"
                  "3,0.5,6,0.0278,pressure,0.004,5,0,101,15\n");
  writeTextAtomic(out / "bodies.csv",
                  "time_s,fluid_surface_z_m,bell_depth_m,bell_rest_density_factor,bell_ring_force_N,bell_tilt_deg\n"
                  "0,5,1,1,0,0\n0.1667,5,1.1,1,10,1\n0.3333,5,1.2,0.99,20,2\n");
  const std::string page = runReportHtml(out);
  EXPECT_EQ(vertexCount(svgById(page, "sim-kinetic-energy")), 4u);
  EXPECT_EQ(vertexCount(svgById(page, "sim-step")), 3u);  // frame 0 has no step
  EXPECT_EQ(vertexCount(seriesOf(svgById(page, "sim-iterations"), "density solve")), 3u);
  // The one cap hit (frame 2) is marked on the density solve's line at frame 2.
  const std::string capMarks = seriesOf(svgById(page, "sim-iterations"), "stopped at the cap");
  EXPECT_EQ(count(capMarks, "<circle"), 1u);
  const auto density = polylines(seriesOf(svgById(page, "sim-iterations"), "density solve"));
  ASSERT_EQ(density.size(), 1u);
  std::smatch mark;
  ASSERT_TRUE(std::regex_search(capMarks, mark, std::regex("cx=\"([^\"]*)\" cy=\"([^\"]*)\"")));
  EXPECT_NEAR(std::stod(mark[1]), density[0][1].x, 0.1);
  EXPECT_NEAR(std::stod(mark[2]), density[0][1].y, 0.1);
  EXPECT_EQ(vertexCount(svgById(page, "sim-caps")), 4u);
  EXPECT_EQ(vertexCount(seriesOf(svgById(page, "bodies-fig3"), "bell depth")), 3u);
  EXPECT_EQ(vertexCount(seriesOf(svgById(page, "bodies-fig3"), "bell ring force")), 3u);
  EXPECT_EQ(vertexCount(svgById(page, "bodies-tilt")), 3u);
  EXPECT_EQ(svgById(page, "bodies-margin"), "");  // no column: no plot
  EXPECT_EQ(count(svgById(page, "time-stages"), "class=\"bar\""), 2u);
}

TEST(RunReport, AFolderThatIsNotARunIsAnErrorNamingRunJson) {
  TempDir dir;
  writeTextAtomic(dir.path() / "report.html", "old");
  test::expectErrorNamingPath([&] { writeRunReport(dir.path()); }, dir.path() / "run.json", "not a kurage run");
  EXPECT_EQ(readText(dir.path() / "report.html"), "old");
  test::expectErrorNamingPath([&] { writeRunReport(dir.path() / "missing"); }, dir.path() / "missing", "no such folder");
}

TEST(RunReport, ADamagedRecordIsAnErrorNamingItAndThePageStaysAsItWas) {
  TempDir dir;
  const fs::path out = fakeRun(dir.path(), "complete");
  const std::string whole = readText(out / "run.json");
  writeTextAtomic(out / "report.html", "old");
  for (const std::string& damaged : {whole.substr(0, whole.size() / 2), std::string("[1, 2]"), std::string()}) {
    writeTextAtomic(out / "run.json", damaged);
    test::expectErrorNamingPath([&] { writeRunReport(out); }, out / "run.json");
    EXPECT_EQ(readText(out / "report.html"), "old");
  }
  writeTextAtomic(out / "run.json", whole);
  const std::string header = "frame,time_s,steps,mean_step_s,mean_density_error,particles,kinetic_energy_J\n";
  writeTextAtomic(out / "sim_frames.csv", header + "0,0,0,,,10,abc\n");
  test::expectErrorNamingPath([&] { writeRunReport(out); }, out / "sim_frames.csv", "not a number");
  writeTextAtomic(out / "sim_frames.csv", header + "0,0,0,,,10\n");
  test::expectErrorNamingPath([&] { writeRunReport(out); }, out / "sim_frames.csv", "line 2");
  EXPECT_EQ(readText(out / "report.html"), "old");
  for (const auto& entry : fs::directory_iterator(out))
    EXPECT_NE(entry.path().extension(), ".tmp") << "a temporary was left: " << entry.path();
}

TEST(RunReport, ALivePageRefreshesUntilTheRunEnds) {
  TempDir dir;
  const fs::path out = fakeRun(dir.path(), "running");
  LiveRunReport live(out, 3600.0);
  live.update({"render", 0, 7, 0.0, -1.0});
  std::string page = readText(out / "report.html");
  EXPECT_NE(page.find("http-equiv=\"refresh\""), std::string::npos);
  EXPECT_NE(page.find("<progress id=\"progress\" value=\"0\" max=\"7\">"), std::string::npos);
  live.update({"render", 3, 7, 3.0, 4.0});  // within the interval: not rewritten
  EXPECT_EQ(readText(out / "report.html"), page);
  EXPECT_EQ(page.find("left in the run"), std::string::npos) << "not known yet";
  live.update({"render", 7, 7, 7.0, 0.0, -1, 90.0});  // a stage's end always is
  page = readText(out / "report.html");
  EXPECT_NE(page.find("7 of 7 frames"), std::string::npos);
  EXPECT_NE(page.find(" left in the run"), std::string::npos) << "the run's forecast (pipeline/estimate.h)";
  nlohmann::json run = nlohmann::json::parse(readText(out / "run.json"));
  run["status"] = "complete";
  writeTextAtomic(out / "run.json", run.dump());
  live.finish();
  page = readText(out / "report.html");
  EXPECT_EQ(page.find("<script"), std::string::npos);
  EXPECT_NE(page.find("class=\"status complete\""), std::string::npos);
}

TEST(StudyReport, RunsDoneFailedAndPending) {
  const Study study = loadStudy(test::sourceDir() / "scenes/studies/dam_break_cfl.json");  // 7 runs
  std::vector<StudyRow> rows(3);
  for (size_t i = 0; i < rows.size(); ++i) {
    rows[i].knobLabels = {knobSettings(study.knobs[0])[i].label};
    rows[i].ok = i != 1;
    rows[i].error = 0.05 * double(i + 1);
    rows[i].totalSeconds = 10.0 / double(i + 1);
    rows[i].figures.assign(study.measure->figures.size(), 1.0);
  }
  rows[1].message = "simulation stopped: <nan>";
  TempDir dir;
  std::string page = studyReportHtml(study, rows, dir.path(), true);
  EXPECT_NE(page.find("http-equiv=\"refresh\""), std::string::npos);
  EXPECT_EQ(count(page, "<tr class=\"pending\">"), 4u);
  EXPECT_EQ(count(page, "<tr class=\"failed\">"), 1u);
  EXPECT_NE(page.find("id=\"warnings\""), std::string::npos);
  EXPECT_NE(page.find("simulation stopped: &lt;nan&gt;"), std::string::npos);
  EXPECT_EQ(vertexCount(seriesOf(svgById(page, "study"), "cfl")), 2u);  // the runs that succeeded
  page = studyReportHtml(study, rows, dir.path(), false);
  EXPECT_EQ(page.find("<script"), std::string::npos);
  EXPECT_NE(page.find("Cheapest setting within the accepted error: cfl = " + rows[0].knobLabels[0]), std::string::npos);
}

// ---- kurage report ----

TEST(ReportCommand, ExitStatusesAsDocumented) {
  TempDir dir;
  const fs::path log = dir.path() / "log.txt";
  EXPECT_EQ(test::runKurage("report --help", log), 0);
  EXPECT_EQ(test::runKurage("report", log), 2) << readText(log);
  EXPECT_EQ(test::runKurage("report " + dir.path().string(), log), 1);
  EXPECT_NE(readText(log).find((dir.path() / "run.json").string()), std::string::npos) << readText(log);
  const fs::path out = fakeRun(dir.path(), "complete");
  EXPECT_EQ(test::runKurage("report " + out.string(), log), 0) << readText(log);
  EXPECT_TRUE(fs::exists(out / "report.html"));
}

}  // namespace
}  // namespace kurage::pipeline
