// The report pages in a real browser (label `clients`): Debian's Chromium (installed by
// .ci/install-deps), headless, opens OUT/report.html of the tiny jellyfish from file:// with no
// network. A copy of the page beside it gets two scripts: one first in <head> that records
// every error (a script's, a resource that failed to load, console.error), one last in <body>
// that, once the page and the film's metadata have loaded, writes what it finds into the DOM:
// each image's natural width, the video's duration, the vertices of each plot's series, the
// warnings box. The test reads that from --dump-dom, scans Chromium's log for console messages
// (the page writes none), and compares with OUT: every image loaded, the video lasts as long as
// the film (where Chromium can decode H.264), each plot holds every value of sim_frames.csv or
// bodies.csv, the warnings box shows for a run whose solver hit its iteration cap and not for a
// clean one. A page with a frame removed must fail the image check (the check can fail). A
// screenshot of each page is written to build/test_output/report_browser/. Without chromium on
// the PATH the tests are skipped.
#include "pipeline/io/csv.h"
#include "pipeline/io/files.h"
#include "render/image.h"

#include "image_test.h"
#include "test_util.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>

namespace kurage::pipeline {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

const char* const kCapture = R"(<script>
window.__kurageErrors = [];
window.addEventListener('error', function (e) {
  var t = e.target;
  window.__kurageErrors.push(t && t !== window && (t.src || t.currentSrc) ? 'failed to load ' + (t.src || t.currentSrc)
                                                                          : 'error: ' + e.message);
}, true);
window.addEventListener('unhandledrejection', function (e) { window.__kurageErrors.push('rejection: ' + e.reason); });
var kurageConsoleError = console.error;
console.error = function () { window.__kurageErrors.push('console.error: ' + Array.from(arguments).join(' ')); };
</script>
)";

const char* const kCheck = R"(<script>
window.addEventListener('load', function () {
  var video = document.getElementById('video'), done = false;
  function report(videoState) {
    if (done) return;
    done = true;
    var r = {errors: window.__kurageErrors, images: [], plots: {}, warnings: null, video: videoState,
             canPlayMp4: document.createElement('video').canPlayType('video/mp4; codecs="avc1.42E01E"')};
    document.querySelectorAll('img').forEach(function (i) {
      r.images.push({src: i.getAttribute('src'), complete: i.complete, width: i.naturalWidth});
    });
    document.querySelectorAll('svg.plot').forEach(function (svg) {
      var box = svg.viewBox.baseVal, series = {};
      svg.querySelectorAll('g.series').forEach(function (g) {
        var n = 0, inside = true;
        g.querySelectorAll('polyline').forEach(function (p) {
          for (var k = 0; k < p.points.numberOfItems; ++k) {
            var q = p.points.getItem(k);
            ++n;
            if (!(q.x >= 0 && q.y >= 0 && q.x <= box.width && q.y <= box.height)) inside = false;
          }
        });
        series[g.getAttribute('data-label')] = {vertices: n, markers: g.querySelectorAll('circle').length, inside: inside,
                                                shown: g.getBoundingClientRect().width > 0};
      });
      r.plots[svg.id] = series;
    });
    var w = document.getElementById('warnings');
    r.warnings = w ? w.innerText : null;
    var out = document.createElement('pre');
    out.id = 'kurage-check';
    out.textContent = encodeURIComponent(JSON.stringify(r));
    document.body.appendChild(out);
  }
  if (!video) return report(null);
  if (video.readyState >= 1) return report({duration: video.duration});
  video.addEventListener('loadedmetadata', function () { report({duration: video.duration}); });
  video.querySelectorAll('source').forEach(function (s) {
    s.addEventListener('error', function () { report({error: 'the source failed to load'}); });
  });
  setTimeout(function () { report({error: 'no metadata within 4 s'}); }, 4000);
});
</script>
)";

std::string percentDecode(const std::string& s) {
  std::string out;
  for (size_t i = 0; i < s.size(); ++i) {
    if (s[i] == '%' && i + 2 < s.size()) {
      out += char(std::stoi(s.substr(i + 1, 2), nullptr, 16));
      i += 2;
    } else {
      out += s[i];
    }
  }
  return out;
}

struct BrowserResult {
  json check;           // what the page's check found
  std::string console;  // Chromium's log lines of console messages
  std::string log;
};

// Where the screenshots go: build/test_output/report_browser/NAME.png (kept after the test).
fs::path screenshotFile(const std::string& name) {
  const fs::path folder = test::testOutputFolder("report_browser");
  fs::create_directories(folder);
  return folder / (name + ".png");
}

bool haveChromium() { return std::system("command -v chromium > /dev/null 2>&1") == 0; }

std::string chromium(const fs::path& work, const std::string& arguments, const fs::path& stdoutFile, const fs::path& stderrFile) {
  const fs::path profile = work / ("profile-" + stdoutFile.stem().string());
  fs::create_directories(profile);
  const std::string command =
      "timeout 120 chromium --headless=new --no-sandbox --disable-gpu --disable-quic --no-first-run "
      "--disable-background-networking --disable-component-update --disable-sync --disable-extensions "
      "--user-data-dir=" + profile.string() + " " + arguments + " > " + stdoutFile.string() + " 2> " + stderrFile.string();
  const int status = std::system(command.c_str());
  return WIFEXITED(status) && WEXITSTATUS(status) == 0 ? "" : "chromium failed: " + readText(stderrFile);
}

// Opens OUT/report.html (through a checking copy beside it) and takes a screenshot of it,
// WORK/NAME.png, where asked.
BrowserResult openInBrowser(const fs::path& out, const fs::path& work, const std::string& name, bool screenshot = true) {
  std::string page = readText(out / "report.html");
  const size_t head = page.find("<head>") + 6, end = page.rfind("</body>");
  page = page.substr(0, head) + "\n" + kCapture + page.substr(head, end - head) + kCheck + page.substr(end);
  const fs::path copy = out / ("report-check-" + name + ".html");
  writeTextAtomic(copy, page);
  BrowserResult r;
  const fs::path dom = work / (name + "-dom.html"), log = work / (name + "-log.txt");
  const std::string failed = chromium(work, "--enable-logging=stderr --v=0 --virtual-time-budget=4500 --dump-dom file://" + copy.string(), dom, log);
  EXPECT_EQ(failed, "");
  r.log = readText(log);
  std::istringstream lines(r.log);
  for (std::string line; std::getline(lines, line);)
    if (line.find(":CONSOLE") != std::string::npos) r.console += line + "\n";
  const std::string text = readText(dom);
  const size_t at = text.find("<pre id=\"kurage-check\">");
  if (at == std::string::npos) {
    ADD_FAILURE() << "the page's check wrote nothing; log:\n" << r.log;
    return r;
  }
  const size_t from = at + std::string("<pre id=\"kurage-check\">").size();
  r.check = json::parse(percentDecode(text.substr(from, text.find("</pre>", from) - from)));
  fs::remove(copy);
  // The screenshot of the page itself, as a user sees it.
  if (screenshot) {
    const std::string shot = "--hide-scrollbars --window-size=1280,2400 --screenshot=" + screenshotFile(name).string() +
                             " file://" + (out / "report.html").string();
    EXPECT_EQ(chromium(work, shot, work / (name + "-shot-out.txt"), work / (name + "-shot-log.txt")), "");
  }
  return r;
}

size_t finiteValues(const CsvTable& table, const std::string& column) {
  size_t n = 0;
  for (double v : table.numbers(column)) n += std::isfinite(v);
  return n;
}

class ReportInBrowser : public ::testing::Test {
protected:
  // The tiny jellyfish as a user runs it, and a twin whose DFSPH solver is capped at two
  // iterations (simulated only).
  static void SetUpTestSuite() {
    dir_ = new test::TempDir;
    if (!haveChromium()) return;
    const fs::path scene = test::sourceDir() / "tests/scenes/tiny_jellyfish.json";
    ok_ = test::runKurage("run " + scene.string() + " -o " + clean().string(), dir_->path() / "clean.txt") == 0;
    json capped = json::parse(readText(scene));
    capped.erase("$schema");
    capped["fluid"].erase("pressure_stiffness");
    capped["fluid"].erase("pressure_force");
    capped["fluid"]["solver"] = "dfsph";
    capped["fluid"]["max_iterations"] = 2;
    capped["fluid"]["max_density_error"] = 0.01;
    writeTextAtomic(dir_->path() / "capped.json", capped.dump(2));
    ok_ = ok_ && test::runKurage("sim " + (dir_->path() / "capped.json").string() + " -o " + cappedOut().string(),
                                 dir_->path() / "capped.txt") == 0;
  }
  static void TearDownTestSuite() { delete dir_; }
  static fs::path clean() { return dir_->path() / "clean"; }
  static fs::path cappedOut() { return dir_->path() / "capped"; }
  static inline test::TempDir* dir_ = nullptr;
  static inline bool ok_ = false;
  void SetUp() override {
    if (!haveChromium()) GTEST_SKIP() << "chromium is not on the PATH (.ci/install-deps installs it)";
  }
};

TEST_F(ReportInBrowser, ACleanRunLoadsWholeAndPlotsEveryValue) {
  ASSERT_TRUE(ok_) << readText(dir_->path() / "clean.txt");
  const BrowserResult r = openInBrowser(clean(), dir_->path(), "clean");
  EXPECT_EQ(r.console, "") << "the page wrote to the console";
  EXPECT_EQ(r.check["errors"], json::array()) << r.check["errors"].dump();
  // Every frame of the film in the contact sheet (7 < 24), each loaded.
  ASSERT_EQ(r.check["images"].size(), 7u) << r.check.dump();
  for (const json& image : r.check["images"]) {
    EXPECT_TRUE(image["complete"].get<bool>()) << image;
    EXPECT_GT(image["width"].get<int>(), 0) << image;
  }
  // The film: 7 frames at 6 fps.
  if (r.check["canPlayMp4"].get<std::string>().empty()) {
    std::printf("chromium here cannot play H.264: the video's duration is not checked\n");
  } else {
    ASSERT_TRUE(r.check["video"].contains("duration")) << r.check["video"];
    EXPECT_NEAR(r.check["video"]["duration"].get<double>(), 7.0 / 6.0, 0.05);
  }
  // The plots hold every value of the records, inside their area.
  const CsvTable frames = parseCsvTable(readText(clean() / "sim_frames.csv"), "sim_frames.csv");
  const CsvTable bodies = parseCsvTable(readText(clean() / "bodies.csv"), "bodies.csv");
  const json& plots = r.check["plots"];
  const auto vertices = [&](const char* plot, const char* series) {
    EXPECT_TRUE(plots[plot][series]["inside"].get<bool>()) << plot << " " << series;
    EXPECT_TRUE(plots[plot][series]["shown"].get<bool>()) << plot << " " << series;
    return plots[plot][series]["vertices"].get<size_t>();
  };
  EXPECT_EQ(vertices("sim-step", "mean step"), finiteValues(frames, "mean_step_s"));
  EXPECT_EQ(vertices("sim-kinetic-energy", "kinetic energy"), frames.rows.size());
  EXPECT_EQ(vertices("sim-particles", "particles"), frames.rows.size());
  EXPECT_EQ(vertices("sim-density-error", "measured"), finiteValues(frames, "mean_density_error"));
  EXPECT_EQ(vertices("bodies-fig3", "bell depth"), bodies.rows.size());
  EXPECT_EQ(vertices("bodies-fig3", "bell ring force"), bodies.rows.size());
  EXPECT_EQ(vertices("bodies-tilt", "bell"), bodies.rows.size());
  EXPECT_FALSE(plots.contains("sim-iterations"));  // WCSPH: no solver iterations
  EXPECT_TRUE(r.check["warnings"].is_null()) << r.check["warnings"];
  // The screenshot of the page.
  const render::Image shot = render::readPng(screenshotFile("clean"));
  EXPECT_EQ(shot.width(), 1280);
}

TEST_F(ReportInBrowser, ARunThatHitItsIterationCapShowsTheWarningsBox) {
  ASSERT_TRUE(ok_) << readText(dir_->path() / "capped.txt");
  const BrowserResult r = openInBrowser(cappedOut(), dir_->path(), "capped");
  EXPECT_EQ(r.console, "");
  EXPECT_EQ(r.check["errors"], json::array()) << r.check["errors"].dump();
  ASSERT_TRUE(r.check["warnings"].is_string()) << r.check.dump();
  EXPECT_NE(r.check["warnings"].get<std::string>().find("iteration cap"), std::string::npos) << r.check["warnings"];
  const CsvTable frames = parseCsvTable(readText(cappedOut() / "sim_frames.csv"), "sim_frames.csv");
  size_t capped = 0;
  for (double hits : frames.numbers("density_cap_hits")) capped += hits > 0;
  ASSERT_GT(capped, 0u);
  EXPECT_EQ(r.check["plots"]["sim-iterations"]["density solve"]["vertices"].get<size_t>(),
            finiteValues(frames, "density_iterations_per_step"));
  EXPECT_EQ(r.check["plots"]["sim-caps"]["density"]["vertices"].get<size_t>(), frames.rows.size());
  EXPECT_TRUE(r.check["images"].empty());  // simulated only: no frames
  EXPECT_TRUE(r.check["video"].is_null());
}

TEST_F(ReportInBrowser, AMissingFrameFailsTheImageCheck) {
  ASSERT_TRUE(ok_);
  const fs::path broken = dir_->path() / "broken";
  fs::copy(clean(), broken, fs::copy_options::recursive);
  fs::remove(broken / "frames/0003.png");  // after the page was written
  const BrowserResult r = openInBrowser(broken, dir_->path(), "broken", false);
  size_t unloaded = 0;
  for (const json& image : r.check["images"]) unloaded += image["width"].get<int>() == 0;
  EXPECT_EQ(unloaded, 1u) << r.check["images"].dump();
  ASSERT_EQ(r.check["errors"].size(), 1u) << r.check["errors"].dump();
  EXPECT_NE(r.check["errors"][0].get<std::string>().find("0003.png"), std::string::npos);
}

TEST_F(ReportInBrowser, AStudyPageLoadsWholeWithEveryRun) {
  const fs::path study = dir_->path() / "study.json", out = dir_->path() / "study";
  writeTextAtomic(study, json{{"name", "tiny"},
                              {"scene", (test::sourceDir() / "tests/scenes/tiny_dam_break.json").string()},
                              {"knobs", {{{"name", "cfl"}, {"path", "time_step.cfl"}, {"values", {0.2, 0.4}}}}},
                              {"measure", "none"},
                              {"duration", 0.05}}
                             .dump());
  ASSERT_EQ(test::runKurage("study " + study.string() + " -o " + out.string() + " --quiet", dir_->path() / "study.txt"), 0)
      << readText(dir_->path() / "study.txt");
  const BrowserResult r = openInBrowser(out, dir_->path(), "study");
  EXPECT_EQ(r.console, "");
  EXPECT_EQ(r.check["errors"], json::array()) << r.check["errors"].dump();
  EXPECT_EQ(r.check["plots"]["study"]["total"]["markers"].get<size_t>(), 2u);  // a marker a run
  EXPECT_TRUE(r.check["warnings"].is_null());
}

}  // namespace
}  // namespace kurage::pipeline
