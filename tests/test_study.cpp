// kurage study (label `unit`): the machinery on a tiny sweep (rows, plot, summary, a failed run
// as a row), strict study files (exit 2 naming the JSON path), JSON paths into scenes, and the
// measures of pipeline/analysis/ against answers known in closed form.
#include "pipeline/io/files.h"
#include "pipeline/analysis/body_measures.h"
#include "pipeline/analysis/series.h"
#include "pipeline/analysis/still_tank.h"
#include "pipeline/analysis/surface_distance.h"
#include "pipeline/studies/study.h"
#include "render/image.h"
#include "sim/kernels.h"
#include "test_util.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <sstream>

using namespace kurage;
using namespace kurage::pipeline;
using kurage::test::TempDir;

namespace {

std::vector<std::vector<std::string>> readCsv(const std::filesystem::path& file) {
  std::vector<std::vector<std::string>> rows;
  std::stringstream text(readText(file));
  std::string line;
  while (std::getline(text, line)) {
    std::vector<std::string> fields;
    std::string field;
    bool quoted = false;
    for (char c : line) {
      if (c == '"') quoted = !quoted;
      else if (c == ',' && !quoted) {
        fields.push_back(field);
        field.clear();
      } else field += c;
    }
    fields.push_back(field);
    rows.push_back(fields);
  }
  return rows;
}

size_t column(const std::vector<std::string>& header, const std::string& name) {
  for (size_t i = 0; i < header.size(); ++i)
    if (header[i] == name) return i;
  ADD_FAILURE() << "no column " << name;
  return 0;
}

// Two values of the adaptive step's CFL factor on the tiny dam break (200 particles, 0.3 s).
nlohmann::json tinyStudy() {
  return {{"name", "tiny"},
          {"scene", (test::sourceDir() / "tests/scenes/tiny_dam_break.json").string()},
          {"knobs", {{{"name", "cfl"}, {"path", "time_step.cfl"}, {"values", {0.2, 0.4}}}}},
          {"measure", "dam_break_front"},
          {"duration", 0.3},
          {"error_threshold", 0.5},
          {"reference_data", (test::sourceDir() / "tests/data/martin_moyce_1952.csv").string()}};
}

std::string writeStudy(const TempDir& dir, const nlohmann::json& study, const char* name = "study.json") {
  const auto file = dir.path() / name;
  writeTextAtomic(file, study.dump(2));
  return file.string();
}

}  // namespace

TEST(Study, TinySweepWritesRowsPlotAndSummary) {
  TempDir dir;
  const std::string file = writeStudy(dir, tinyStudy());
  const auto out = dir.path() / "out";
  ASSERT_EQ(test::runKurage("study " + file + " -o " + out.string() + " --threads 1", dir.path() / "log.txt"), 0)
      << readText(dir.path() / "log.txt");
  const auto csv = readCsv(out / "study.csv");
  ASSERT_EQ(csv.size(), 3u) << "header and one row per value";
  const auto& header = csv[0];
  EXPECT_EQ(header[0], "cfl");
  EXPECT_EQ(csv[1][0], "0.2");
  EXPECT_EQ(csv[2][0], "0.4");
  for (size_t r = 1; r <= 2; ++r) {
    EXPECT_EQ(csv[r][column(header, "status")], "ok");
    const double error = std::stod(csv[r][column(header, "error")]);
    EXPECT_GT(error, 0.0);
    EXPECT_LT(error, 1.0);
    EXPECT_GT(std::stod(csv[r][column(header, "total_s")]), 0.0);
    EXPECT_GT(std::stod(csv[r][column(header, "sim_density_s")]), 0.0);
  }
  // Half the CFL factor, about twice the steps.
  const double steps02 = std::stod(csv[1][column(header, "steps")]), steps04 = std::stod(csv[2][column(header, "steps")]);
  EXPECT_GT(steps02, 1.5 * steps04);
  const render::Image plot = render::readPng(out / "study.png");
  EXPECT_GT(plot.width(), 100);
  for (const char* figure : {"study.svg", "study.pdf", "study.gp"}) EXPECT_TRUE(std::filesystem::exists(out / figure)) << figure;
  const std::string md = readText(out / "study.md");
  EXPECT_NE(md.find("Cheapest setting within the accepted error"), std::string::npos) << md;
  EXPECT_NE(md.find("cfl = 0.4"), std::string::npos) << md;
}

TEST(Study, FigureIsRedrawnFromItsCsv) {
  TempDir dir;
  const std::string file = writeStudy(dir, tinyStudy());
  const auto out = dir.path() / "out";
  ASSERT_EQ(test::runKurage("study " + file + " -o " + out.string() + " --threads 1", dir.path() / "log.txt"), 0);
  // The rows read back from study.csv draw the same figure: the same gnuplot script.
  const auto figure = dir.path() / "again.png";
  ASSERT_EQ(test::runKurage("study " + file + " --replot " + (out / "study.csv").string() + " -o " + figure.string(),
                            dir.path() / "replot.txt"),
            0)
      << readText(dir.path() / "replot.txt");
  std::string original = readText(out / "study.gp"), redrawn = readText(dir.path() / "again.gp");
  for (std::string* gp : {&original, &redrawn}) gp->erase(gp->find("set terminal"));
  EXPECT_EQ(redrawn, original);
  EXPECT_EQ(readText(dir.path() / "again.pdf").substr(0, 5), "%PDF-");
  // A CSV of another study is refused, naming the file.
  const auto other = dir.path() / "other.csv";
  writeTextAtomic(other, "x,status\n1,ok\n");
  EXPECT_EQ(test::runKurage("study " + file + " --replot " + other.string() + " -o " + figure.string(),
                            dir.path() / "bad.txt"),
            1);
  EXPECT_NE(readText(dir.path() / "bad.txt").find("other.csv"), std::string::npos);
}

TEST(Study, VariantsNamingASeriesShareOneLineEachLabelledWithoutTheSeriesName) {
  TempDir dir;
  nlohmann::json study = tinyStudy();
  study["knobs"] = {{{"name", "step"},
                     {"variants",
                      {{{"label", "cfl, 0.2"}, {"series", "cfl"}, {"set", {{"time_step.cfl", 0.2}}}},
                       {{"label", "cfl, 0.4"}, {"series", "cfl"}, {"set", {{"time_step.cfl", 0.4}}}},
                       {{"label", "fixed 0.002"}, {"series", "fixed"}, {"set", {{"time_step.fixed_step", 0.002}}}}}}}};
  const std::string file = writeStudy(dir, study);
  const auto out = dir.path() / "out";
  ASSERT_EQ(test::runKurage("study " + file + " -o " + out.string() + " --threads 1", dir.path() / "log.txt"), 0)
      << readText(dir.path() / "log.txt");
  const std::string gp = readText(out / "study.gp");
  // Two lines (cfl with two points, fixed with one) and the accepted error's line.
  const auto block = [&](int k) {
    const std::string start = "$series" + std::to_string(k) + " << EOD\n";
    const size_t at = gp.find(start);
    if (at == std::string::npos) return std::string();
    return gp.substr(at + start.size(), gp.find("EOD", at + start.size()) - at - start.size());
  };
  const std::string cfl = block(0), fixed = block(1);
  EXPECT_EQ(std::count(cfl.begin(), cfl.end(), '\n'), 2) << gp;
  EXPECT_EQ(std::count(fixed.begin(), fixed.end(), '\n'), 1) << gp;
  EXPECT_NE(block(2), "") << gp;
  EXPECT_EQ(block(3), "") << gp;
  EXPECT_NE(gp.find("title \"cfl\""), std::string::npos) << gp;
  EXPECT_NE(gp.find("title \"fixed\""), std::string::npos) << gp;
  EXPECT_NE(block(0).find("\"0.2\""), std::string::npos) << block(0);  // "cfl, 0.2" less "cfl, "
  EXPECT_EQ(block(0).find("cfl"), std::string::npos) << block(0);
  EXPECT_NE(block(1).find("\"0.002\""), std::string::npos) << block(1);  // "fixed 0.002" less "fixed "
}

TEST(Study, AFailedRunIsARowWithItsMessage) {
  // A step floor above the CFL bound stops the second run at once.
  nlohmann::json study = tinyStudy();
  study["measure"] = "none";
  study.erase("error_threshold");
  study.erase("reference_data");
  study["knobs"] = {{{"path", "time_step.min_step"}, {"values", {1e-5, 0.04}}}};
  TempDir dir;
  std::vector<StudyRow> rows;
  StudyOptions options;
  options.outDir = dir.path() / "out";
  options.progress = false;
  rows = runStudy(parseStudy(study, dir.path() / "study.json"), options);
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_TRUE(rows[0].ok) << rows[0].message;
  EXPECT_FALSE(rows[1].ok);
  EXPECT_NE(rows[1].message.find("simulation stopped"), std::string::npos) << rows[1].message;
  const auto csv = readCsv(options.outDir / "study.csv");
  ASSERT_EQ(csv.size(), 3u);
  EXPECT_EQ(csv[2][column(csv[0], "status")], "failed");
  EXPECT_NE(csv[2].back().find("simulation stopped"), std::string::npos);
  EXPECT_TRUE(std::filesystem::exists(options.outDir / "study.png"));
}

TEST(Study, TwoKnobsRunEveryCombinationFirstKnobFastest) {
  nlohmann::json study = tinyStudy();
  study["measure"] = "none";
  study["duration"] = 0.05;
  study["knobs"].push_back({{"name", "walls"},
                            {"variants",
                             {{{"label", "no slip"}, {"set", {{"container.walls", "no_slip"}}}},
                              {{"label", "free slip"}, {"set", {{"container.walls", "free_slip"}}}}}}});
  TempDir dir;
  StudyOptions options;
  options.outDir = dir.path();
  options.progress = false;
  const std::vector<StudyRow> rows = runStudy(parseStudy(study, dir.path() / "study.json"), options);
  ASSERT_EQ(rows.size(), 4u);
  const std::vector<std::vector<std::string>> expected{
      {"0.2", "no slip"}, {"0.4", "no slip"}, {"0.2", "free slip"}, {"0.4", "free slip"}};
  for (size_t i = 0; i < 4; ++i) EXPECT_EQ(rows[i].knobLabels, expected[i]);
}

TEST(Study, BadStudyFilesAreRefusedWithExit2NamingTheJsonPath) {
  TempDir dir;
  struct Case {
    const char* what;
    nlohmann::json study;
    const char* path;
  };
  std::vector<Case> cases;
  {
    nlohmann::json s = tinyStudy();
    s["knobs"][0]["valuez"] = {1};
    cases.push_back({"unknown key", s, "knobs[0].valuez"});
  }
  {
    nlohmann::json s = tinyStudy();
    s["knobs"][0]["values"] = {0.4, 5.0};  // cfl must be <= 1
    cases.push_back({"value the scene refuses", s, "knobs[0].values[1]"});
  }
  {
    nlohmann::json s = tinyStudy();
    s["knobs"][0]["path"] = "time_step.cfl_factor";  // not a scene key
    cases.push_back({"path that is no scene key", s, "knobs[0].values[0]"});
  }
  {
    nlohmann::json s = tinyStudy();
    s["knobs"][0]["path"] = "fluid_blocks[3].max";
    cases.push_back({"index past the end", s, "knobs[0].path"});
  }
  {
    nlohmann::json s = tinyStudy();
    s["measure"] = "accuracy";
    cases.push_back({"unknown measure", s, "measure"});
  }
  {
    nlohmann::json s = tinyStudy();
    s.erase("error_threshold");
    cases.push_back({"missing threshold", s, "error_threshold"});
  }
  {
    nlohmann::json s = tinyStudy();
    s["measure"] = "hydrostatic_tank";
    s["average_from"] = 1.0;  // after the 0.3 s duration
    cases.push_back({"still tank averaged after its end", s, "average_from"});
  }
  {
    nlohmann::json s = tinyStudy();
    s["measure"] = "hydrostatic_tank";
    s["knobs"][0] = {{"path", "gravity"}, {"values", {{0, 0, -9.81}, {0, 0, 0}}}};
    cases.push_back({"still tank without gravity", s, "knobs[0].values[1]"});
  }
  {
    nlohmann::json s = tinyStudy();
    s["scene"] = std::string(300, 's') + ".json";  // longer than a file name may be
    cases.push_back({"scene name too long for the file system", s, "scene"});
  }
  for (const Case& c : cases) {
    const std::string file = writeStudy(dir, c.study, "bad.json");
    const auto log = dir.path() / "log.txt";
    EXPECT_EQ(test::runKurage("study " + file + " -o " + (dir.path() / "out").string(), log), 2) << c.what;
    const std::string message = readText(log);
    EXPECT_NE(message.find(file + ": " + c.path + ":"), std::string::npos) << c.what << ": " << message;
    EXPECT_FALSE(std::filesystem::exists(dir.path() / "out" / "study.csv")) << c.what << ": nothing runs";
  }
}

TEST(Study, CommittedStudiesAreValid) {
  // Every study under scenes/studies/ still fits the scenes it edits (a renamed scene key fails here).
  size_t studies = 0;
  for (const auto& entry : std::filesystem::directory_iterator(test::sourceDir() / "scenes/studies")) {
    if (entry.path().extension() != ".json") continue;
    ++studies;
    EXPECT_NO_THROW(loadStudy(entry.path())) << entry.path();
  }
  EXPECT_GE(studies, 5u);
}

TEST(Study, EveryMeasureHasAScorer) {
  for (const StudyMeasure& m : studyMeasures()) EXPECT_TRUE(hasStudyScorer(m.name)) << m.name;
  EXPECT_FALSE(hasStudyScorer("no_such_measure"));
  Study study;
  study.measure = findStudyMeasure("none");
  EXPECT_TRUE(startStudyScorer(study));
}

TEST(JsonPath, SetsNestedKeysAndArrayElements) {
  nlohmann::json doc = {{"bodies", {{{"spacing", 0.5}}}}};
  setJsonPath(doc, "bodies[0].spacing", 0.25);
  setJsonPath(doc, "time_step.fixed_step", 0.001);
  setJsonPath(doc, "bodies[0].muscles", nlohmann::json::array());
  EXPECT_EQ(doc["bodies"][0]["spacing"], 0.25);
  EXPECT_EQ(doc["time_step"]["fixed_step"], 0.001);
  EXPECT_TRUE(doc["bodies"][0]["muscles"].is_array());
  EXPECT_THROW(setJsonPath(doc, "bodies[1].spacing", 1), std::invalid_argument);
  EXPECT_THROW(setJsonPath(doc, "bodies.spacing", 1), std::invalid_argument);
  EXPECT_THROW(setJsonPath(doc, "time_step.fixed_step.x", 1), std::invalid_argument);
  EXPECT_THROW(setJsonPath(doc, "fluid..spacing", 1), std::invalid_argument);
  EXPECT_THROW(setJsonPath(doc, "bodies[x]", 1), std::invalid_argument);
}

TEST(Measures, SeriesErrorUsesOnlyReferencePointsInsideTheRun) {
  const std::vector<SeriesPoint> measured{{0, 1}, {1, 2}, {2, 3}};
  const SeriesError e = meanRelativeError(measured, {{0.5, 1.5}, {1.5, 2.0}, {3.0, 1.0}});
  EXPECT_EQ(e.points, 2);
  EXPECT_NEAR(e.meanRelative, 0.5 * (0.0 + 0.25), 1e-12);
}

TEST(Measures, RmseOfAConstantOffsetIsTheOffset) {
  render::Image a(4, 3, {0.2f, 0.2f, 0.2f, 1}), b(4, 3, {0.2f, 0.2f, 0.2f, 1});
  EXPECT_EQ(render::imageRmse(a, b), 0.0);
  const float shifted = render::srgbToLinear(render::linearToSrgb(0.2f) + 0.1f);
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 4; ++x) b.at(x, y) = {shifted, shifted, shifted, 1};
  EXPECT_NEAR(render::imageRmse(a, b), 0.1, 1e-5);
  EXPECT_THROW(render::imageRmse(a, render::Image(2, 2)), std::invalid_argument);
}

TEST(Measures, ExactFieldOfOneBlobCrossesAtTheAnalyticRadius) {
  // One particle: the surface f = T is the sphere R sqrt(1 - sqrt(T / s)). The exact field finds
  // it to bisection precision; the level set within the 0.25 voxel of render/surfacing.h.
  render::MetaballParams params;
  params.radius = 2.0f;
  params.threshold = 0.6f;
  params.voxelSize = 0.25f;
  const Eigen::Vector3f centre(0.3f, -0.2f, 0.1f);
  const MetaballField field({centre}, params);
  const double r0 = params.radius * std::sqrt(1.0 - std::sqrt(double(params.threshold)));
  EXPECT_NEAR(field(centre.cast<double>() + Eigen::Vector3d(r0, 0, 0)), params.threshold, 1e-6);
  const render::LevelSet ls = render::buildMetaballLevelSet({centre}, params);
  const SurfaceDistance d = surfaceDistance(ls, field, params, 200);
  EXPECT_EQ(d.rays, 200);
  EXPECT_EQ(d.misses, 0);
  EXPECT_GT(d.max, 0.0);
  EXPECT_LT(d.max, 0.25 * params.voxelSize);
  EXPECT_LE(d.mean, d.max);
}

TEST(Measures, MembraneLeakCountsFluidBelowTheLowestBodyParticle) {
  sim::ParticleSet p;
  p.add(0, 0, 5.0f, 0, 0, 0, 1000, 1, 0, 1);  // membrane particle
  p.add(0, 0, 6.0f, 0, 0, 0, 1000, 1, 1, 0);  // above
  p.add(0, 0, 4.6f, 0, 0, 0, 1000, 1, 2, 0);  // below, but within half a spacing
  p.add(0, 0, 4.4f, 0, 0, 0, 1000, 1, 3, 0);  // through
  const MembraneLeak leak = membraneLeak(p, 1, 1.0f);
  EXPECT_EQ(leak.fluid, 3u);
  EXPECT_EQ(leak.leaked, 1u);
}

// The loaded sheet's pressure counts only sheet particles with fluid within 0.7 h, the fluid's only
// particles within h of the sheet.
TEST(Measures, MembraneLoadReadsTheLoadedSheetAndTheFluidOnIt) {
  sim::ParticleSet p;
  int64_t id = 0;
  for (int k = 0; k < 10; ++k) p.add(float(k), 0, 5.0f, 0, 0, 0, 1000, 1, id++, 1);  // sheet along x
  p.add(0, 0, 6.0f, 0, 0, 0, 1000, 1, id++, 0);   // fluid on the sheet's first particle
  p.add(0, 0, 9.0f, 0, 0, 0, 1000, 1, id++, 0);   // fluid far above
  for (size_t i = 0; i < p.size(); ++i) p.pressure[i] = p.kind[i] == 1 ? (p.x[i] == 0.0f ? 4000.0f : 100.0f) : 0.0f;
  p.pressure.back() = 7000.0f;  // the far fluid particle: not against the sheet
  const MembraneLoad load = membraneLoad(p, 1, 1.5f);  // 0.7 h = 1.05 m: one sheet particle is loaded
  EXPECT_EQ(load.sheetParticles, 1u);
  EXPECT_EQ(load.sheetPressure90, 4000.0);
  EXPECT_EQ(load.fluidParticles, 1u);
  EXPECT_EQ(load.fluidPressure50, 0.0);
}

// A lattice 10 m deep at rest with the hydrostatic pressure reads no error; each slab's pressure
// 3 % high reads 3 %, and a tank that sank by one spacing reads its surface 10 % low.
TEST(Measures, HydrostaticTrackReadsTheSlabsAndTheSurface) {
  sim::SimParams params;
  params.fluid.spacing = 1.0f;
  params.fluid.supportRadius = 2.0f;  // h = 2 m: slabs from 4 to 6 m above the floor
  params.gravity = Eigen::Vector3f(0, 0, -6);
  params.container.max = Eigen::Vector3f(10, 10, 12);
  auto tank = [&](float scale, float drop) {
    sim::ParticleSet p;
    int64_t id = 0;
    for (int k = 0; k < 10; ++k)
      for (int j = 0; j < 10; ++j)
        for (int i = 0; i < 10; ++i) {
          const float z = 0.5f + float(k) - drop;
          p.add(0.5f + float(i), 0.5f + float(j), z, 0, 0, 0, 1000, 1000, id++, 0);
          p.pressure.back() = scale * 1000.0f * 6.0f * (10.0f - drop - z);
        }
    return p;
  };
  HydrostaticTrack still(params, 10.0);
  still.record(tank(1.0f, 0.0f));
  EXPECT_NEAR(still.freeSurface(tank(1.0f, 0.0f)), 10.0, 1e-6);
  EXPECT_EQ(still.samples(), 1);
  EXPECT_EQ(still.slabs(), 1);  // [4, 6), two spacings thick: wholly inside [2h, H - 2h]
  EXPECT_NEAR(still.surfaceError(), 0.0, 1e-8);
  EXPECT_NEAR(still.worstSlab(), 0.0, 1e-6);
  EXPECT_NEAR(still.worstSlabAgainstWeight(), 0.0, 1e-6) << "the pressure carries the water above it";
  EXPECT_NEAR(still.worstLayer(), 0.0, 1e-6);
  // A pressure alternating from layer to layer pushes nothing: the symmetric force on a lattice
  // particle, sum_j (p_i + p_j) grad W_ij, reads differences p_{k+m} - p_{k-m} of layers as far
  // above as below, which have the same parity (at any h; here the scenes' 1.5 l and DFSPH's 2 l).
  // So no solve sees it, and the slabs (two layers) do not read it either: a pressure 2 % over the
  // depth's in odd layers and 2 % under in even ones reads no error on slabs and 2 % on layers.
  for (const float support : {1.5f, 2.0f}) {
    const sim::CubicSplineKernel w(support);
    auto force = [&](auto pressure) {  // on a lattice particle of layer 5, from all its neighbours
      Eigen::Vector3d f = Eigen::Vector3d::Zero();
      for (int dz = -2; dz <= 2; ++dz)
        for (int dy = -2; dy <= 2; ++dy)
          for (int dx = -2; dx <= 2; ++dx) {
            const Eigen::Vector3d d(dx, dy, dz);
            if (d.norm() == 0.0 || d.norm() >= support) continue;
            f += (pressure(5) + pressure(5 + dz)) * double(w.derivative(float(d.norm()))) * d / d.norm();
          }
      return f;
    };
    EXPECT_LT(force([](int k) { return k % 2 ? 1.0 : -1.0; }).norm(), 1e-9) << "a pure alternation pushes nothing, h " << support;
    EXPECT_GT(force([](int k) { return 1.0 * (10 - k); }).norm(), 0.1) << "a gradient pushes, h " << support;
  }
  sim::ParticleSet alternating = tank(1.0f, 0.0f);
  for (size_t i = 0; i < alternating.size(); ++i)
    alternating.pressure[i] *= int(std::floor(alternating.z[i])) % 2 ? 1.02f : 0.98f;
  HydrostaticTrack layered(params, 10.0);
  layered.record(alternating);
  EXPECT_NEAR(layered.worstSlab(), 0.0, 1e-3) << "a slab holds one layer of each sign";
  EXPECT_NEAR(layered.worstLayer(), 0.02, 1e-6);
  HydrostaticTrack high(params, 10.0);
  high.record(tank(1.03f, 0.0f));
  EXPECT_NEAR(high.worstSlab(), 0.03, 1e-6);
  EXPECT_NEAR(high.worstSlabAgainstWeight(), 0.03, 1e-6);
  HydrostaticTrack sunk(params, 10.0);
  sunk.record(tank(1.0f, 1.0f));
  EXPECT_NEAR(sunk.surfaceError(), 0.1, 1e-8);
  EXPECT_NEAR(sunk.worstSlab(), 0.0, 1e-6) << "the depth is measured from the sample's own surface";
  EXPECT_GT(sunk.worstSlabBelowFilled(), 0.1) << "and, apart, from the filled height";
  EXPECT_NEAR(sunk.worstSlabAgainstWeight(), 0.0, 1e-6);
  // Packed closer: the same water at 0.9 of the spacing from the floor up holds the same pressure
  // per weight, which the depth below its surface (0.9 of the lattice's) reads 11 % high.
  HydrostaticTrack packed(params, 10.0);
  sim::ParticleSet dense = tank(1.0f, 0.0f);
  for (size_t i = 0; i < dense.size(); ++i) dense.z[i] *= 0.9f;
  packed.record(dense);
  EXPECT_NEAR(packed.worstSlabAgainstWeight(), 0.0, 0.02) << "the pressure carries the water above it";
  EXPECT_GT(packed.worstSlab(), 0.05);
  // The surface is where the water ends, not where the top particles stand in columns: the top
  // layer moved sideways by up to a spacing (so some one-spacing columns lose their top particle
  // and others gain two, which the mean of each column's top particle read 0.22 m low here) reads
  // the same surface. A top layer spread by +-0.3 of a spacing in height reads within 0.02 m.
  sim::ParticleSet shuffled = tank(1.0f, 0.0f);
  for (size_t i = 0; i < shuffled.size(); ++i)
    if (shuffled.z[i] > 9.0f) {
      shuffled.x[i] += 0.9f * std::sin(1.7f * float(i));
      shuffled.y[i] += 0.9f * std::cos(2.3f * float(i));
    }
  EXPECT_NEAR(still.freeSurface(shuffled), 10.0, 1e-6);
  sim::ParticleSet rough = tank(1.0f, 0.0f);
  for (size_t i = 0; i < rough.size(); ++i)
    if (rough.z[i] > 9.0f) rough.z[i] += 0.3f * std::sin(1.7f * float(i));
  EXPECT_NEAR(still.freeSurface(rough), 10.0, 0.02);
  // With h = 1.5 m the strip's edges fall on lattice rows: still exact (half-open columns).
  params.fluid.supportRadius = 1.5f;
  HydrostaticTrack narrow(params, 10.0);
  narrow.record(tank(1.0f, 0.0f));
  EXPECT_GT(narrow.slabs(), 0);
  EXPECT_NEAR(narrow.worstSlabAgainstWeight(), 0.0, 1e-6);
  sim::ParticleSet moving = tank(1.0f, 0.0f);
  for (size_t i = 0; i < moving.size(); ++i) moving.vz[i] = i % 2 ? 2.0f : -2.0f;
  EXPECT_FLOAT_EQ(float(rmsSpeed(moving, 0)), 2.0f);
  EXPECT_EQ(rmsSpeed(moving, 1), 0.0);
}

// What bodies take of the water's level: the volume near the body particles that holds no water,
// weighted 1 up to l beyond their contact distance and falling to 0 at 2 h. A tank 8 x 8 m (its
// floor at z = -0.125, so that the cells of l/2 centre on the rows) with 4 m of water on the lattice
// (l = 0.5 m, h = 1 m, rows at z = 0.25, 0.75, ...) and a sheet of body particles at z = 2 above
// every cell: the rows at 1.75 and 2.25 that the sheet replaced are the 1 m it lacks, the weights
// of the rest balancing their cells' (a lattice without a gap reads 0).
TEST(Measures, BodiesDisplacementIsTheWaterMissingNearTheBodies) {
  sim::SimParams params;
  params.fluid.spacing = 0.5f;
  params.fluid.supportRadius = 2.0f;
  params.container.min = {0, 0, -0.125f};
  params.container.max = {8, 8, 8};
  const float m = params.fluid.restDensity * 0.125f;
  auto tank = [&](float top, std::vector<int> gaps, bool sheet = true) {
    sim::ParticleSet p;
    int64_t id = 0;
    for (int i = 0; i < 16; ++i)
      for (int j = 0; j < 16; ++j)
        for (int k = 0; 0.25f + 0.5f * k < top; ++k)
          if (std::find(gaps.begin(), gaps.end(), k) == gaps.end())
            p.add(0.25f + 0.5f * i, 0.25f + 0.5f * j, 0.25f + 0.5f * k, 0, 0, 0, params.fluid.restDensity, m, id++, 0);
    for (int i = 0; sheet && i < 32; ++i)
      for (int j = 0; j < 32; ++j)
        p.add(0.125f + 0.25f * i, 0.125f + 0.25f * j, 2.0f, 0, 0, 0, params.fluid.restDensity, m, id++, 1);
    return p;
  };
  EXPECT_EQ(bodiesDisplacement(params, tank(4.0f, {3, 4}, false), 4.125), 0.0) << "no body";
  EXPECT_NEAR(bodiesDisplacement(params, tank(4.0f, {}), 4.125), 0.0, 1e-9) << "no gap";
  EXPECT_NEAR(bodiesDisplacement(params, tank(4.0f, {3, 4}), 4.125), 1.0, 1e-9);
  // Up to the level only: with 3 m of water the air above it is not missing water (1.33 m if it
  // were); the level's cell layer is cut in half.
  EXPECT_NEAR(bodiesDisplacement(params, tank(3.0f, {3, 4}), 3.125), 1.0, 0.1);
  // The body's fluid contact (0.5 m: collisions.fluid_contact 2 x its spacing 0.25 m) moves the
  // weights out: with the rows at 0.75 and 3.25 also missing (w 5/6 each; 1/2 without contact).
  EXPECT_NEAR(bodiesDisplacement(params, tank(4.0f, {1, 3, 4, 6}), 4.125), 1.5, 1e-9);
  params.bodies.resize(1);
  params.bodies[0].spacing = 0.5f;
  params.collisions.fluidContact = 2.0f;
  EXPECT_NEAR(bodiesDisplacement(params, tank(4.0f, {1, 3, 4, 6}), 4.125), 11.0 / 6.0, 1e-9);
}
