#include "pipeline/report/run_report.h"

#include "pipeline/io/csv.h"
#include "pipeline/io/files.h"
#include "pipeline/io/process.h"
#include "pipeline/io/run_lock.h"
#include "pipeline/report/html.h"
#include "pipeline/report/page.h"
#include "pipeline/report/svg_plot.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <map>
#include <sstream>

namespace kurage::pipeline {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

constexpr int kChartWidth = 540, kChartHeight = 300;

// ---- Reading OUT ----

// The value at a path of object keys, or null.
const json* find(const json& j, std::initializer_list<const char*> path) {
  const json* at = &j;
  for (const char* key : path) {
    if (!at->is_object() || !at->contains(key)) return nullptr;
    at = &(*at)[key];
  }
  return at;
}

double number(const json& j, std::initializer_list<const char*> path, double otherwise = NAN) {
  const json* v = find(j, path);
  return v && v->is_number() ? v->get<double>() : otherwise;
}

std::string text(const json& j, std::initializer_list<const char*> path, const std::string& otherwise = "") {
  const json* v = find(j, path);
  return v && v->is_string() ? v->get<std::string>() : otherwise;
}

// A parameter's value as the user wrote it in the scene: numbers short, arrays in brackets.
std::string shown(const json& v) {
  if (v.is_string()) return v.get<std::string>();
  if (v.is_number_integer()) return std::to_string(v.get<int64_t>());
  if (v.is_number()) return formatNumber(v.get<double>(), 6);
  if (v.is_boolean()) return v.get<bool>() ? "true" : "false";
  if (v.is_array()) {
    std::string s = "[";
    for (size_t i = 0; i < v.size(); ++i) s += (i ? ", " : "") + shown(v[i]);
    return s + "]";
  }
  return v.dump();
}

// The frames of a folder named NNNN.EXT, by number.
std::map<int, fs::path> framesIn(const fs::path& folder, const std::string& extension) {
  std::map<int, fs::path> frames;
  std::error_code ec;
  if (!fs::is_directory(folder, ec)) return frames;
  for (const auto& entry : fs::directory_iterator(folder, ec)) {
    const fs::path& p = entry.path();
    const std::string stem = p.stem().string();
    if (p.extension() != extension || stem.empty() || stem.size() > 9 ||
        stem.find_first_not_of("0123456789") != std::string::npos)
      continue;
    frames[std::stoi(stem)] = p;
  }
  return frames;
}

struct FolderSize {
  size_t files = 0;
  uintmax_t bytes = 0;
};
FolderSize folderSize(const fs::path& folder) {
  FolderSize s;
  std::error_code ec;
  for (auto it = fs::recursive_directory_iterator(folder, ec); !ec && it != fs::recursive_directory_iterator(); it.increment(ec))
    if (it->is_regular_file(ec) && it->path().filename().string().front() != '.') {
      ++s.files;
      s.bytes += it->file_size(ec);
    }
  return s;
}

std::string bytesText(uintmax_t bytes) {
  const char* units[] = {"B", "KB", "MB", "GB", "TB"};
  double v = double(bytes);
  int u = 0;
  while (v >= 1000 && u < 4) v /= 1000, ++u;
  return (u == 0 ? std::to_string(bytes) : formatNumber(v, 3)) + " " + units[u];
}

std::optional<CsvTable> readTable(const fs::path& file) {
  if (!fs::exists(file)) return std::nullopt;
  return parseCsvTable(readText(file), file.string());
}

// Everything the page shows, read before any of it is drawn.
struct Run {
  fs::path out;
  json record;
  std::string status;  // complete, running, failed, interrupted, stopped
  std::optional<ProgressState> live;
  std::optional<CsvTable> frames;  // sim_frames.csv
  std::optional<CsvTable> bodies;  // bodies.csv
  std::map<int, fs::path> pngs;
  fs::path film;  // OUT/NAME.mp4, or empty
  double fps = 0.0;
  int frameCount = 0;
  const json& parameters() const { return record["parameters"]; }
  std::string name() const { return text(record, {"parameters", "name"}, out.filename().string()); }
};

Run readRun(const fs::path& out, const std::optional<ProgressState>& live) {
  Run run;
  run.out = out;
  run.live = live;
  const fs::path file = out / "run.json";
  if (!fs::is_directory(out)) throw std::runtime_error(out.string() + ": no such folder");
  if (!fs::exists(file)) throw std::runtime_error(file.string() + ": missing: " + out.string() + " is not a kurage run's output folder");
  try {
    run.record = json::parse(readText(file));
  } catch (const json::exception& e) {
    throw std::runtime_error(file.string() + ": damaged, not JSON (" + e.what() + ")");
  }
  if (!run.record.is_object() || !run.record.contains("parameters") || !run.record["parameters"].is_object())
    throw std::runtime_error(file.string() + ": not a kurage run record (no \"parameters\" object)");
  run.status = text(run.record, {"status"}, "complete");
  if (run.status == "running" && !live && !RunLock::held(out)) run.status = "stopped";
  run.fps = number(run.record, {"parameters", "output", "fps"}, 0.0);
  run.frameCount = int(number(run.record, {"derived", "frame_count"}, 0.0));
  run.frames = readTable(out / "sim_frames.csv");
  run.bodies = readTable(out / "bodies.csv");
  run.pngs = framesIn(out / "frames", ".png");
  const fs::path film = out / (run.name() + ".mp4");
  if (fs::exists(film)) run.film = film;
  return run;
}

// ---- Sections ----

struct Warning {
  std::string message, key;
  bool error = false;
};

std::vector<Warning> warningsOf(const Run& run) {
  std::vector<Warning> warnings;
  if (run.status == "failed" || run.status == "interrupted")
    warnings.push_back({"The run " + run.status + ": " + text(run.record, {"error"}), "error", true});
  if (run.status == "stopped")
    warnings.push_back({"run.json says the run is running, but no process holds the folder's lock: it was killed "
                        "before it could record how it ended (`kurage run ... --resume` continues from the last "
                        "checkpoint)",
                        "status", true});
  if (const json* stages = find(run.record, {"stages"}); stages && stages->is_object())
    for (const auto& [name, stage] : stages->items())
      if (const json* list = find(stage, {"warnings"}); list && list->is_array())
        for (const json& w : *list)
          warnings.push_back({text(w, {"message"}, shown(w)), text(w, {"key"})});
  return warnings;
}

std::string statusLine(const Run& run) {
  std::ostringstream o;
  const std::string& s = run.status;
  o << "<p class=\"status " << s << "\"><span class=\"pill\">" << escapeHtml(s) << "</span> ";
  if (s == "running" && run.live) {
    const ProgressState& p = *run.live;
    o << "<b>" << escapeHtml(p.stage) << "</b>";
    if (p.total > 0) {
      o << ": " << p.done << " of " << p.total << " frames (" << int(100.0 * p.done / p.total) << " %) "
        << "<progress id=\"progress\" value=\"" << p.done << "\" max=\"" << p.total << "\"></progress>";
    }
    o << " · " << escapeHtml(formatDuration(p.seconds)) << " in this stage";
    if (p.secondsLeft >= 0) o << " · about " << escapeHtml(formatDuration(p.secondsLeft)) << " left in it";
    if (p.runSecondsLeft >= 0) o << " · about " << escapeHtml(formatDuration(p.runSecondsLeft)) << " left in the run";
  } else if (s == "running") {
    o << "another process is writing into this folder; this page shows what it has written so far";
  } else {
    double total = 0.0;
    if (const json* stages = find(run.record, {"stages"}); stages && stages->is_object())
      for (const auto& [name, stage] : stages->items()) total += number(stage, {"seconds"}, 0.0);
    o << run.pngs.size() << " frames on disk · " << escapeHtml(formatDuration(total)) << " in the stages";
  }
  o << "</p>\n";
  // The stages of the command, each done, running or to come.
  if (s == "running" && run.live)
    if (const json* planned = find(run.record, {"stages_planned"}); planned && planned->is_array()) {
      o << "<ol class=\"stages\">";
      bool before = true;
      for (const json& stage : *planned) {
        const std::string name = stage.is_string() ? stage.get<std::string>() : shown(stage);
        const bool current = name == run.live->stage;
        if (current) before = false;
        o << "<li class=\"" << (current ? "running" : before ? "done" : "todo") << "\">" << escapeHtml(name);
        if (before && !current)
          if (double sec = number(run.record, {"stages", name.c_str(), "seconds"}); std::isfinite(sec))
            o << " <small>" << escapeHtml(formatDuration(sec)) << "</small>";
        o << "</li>";
      }
      o << "</ol>\n";
    }
  return o.str();
}

std::string warningsBox(const std::vector<Warning>& warnings) {
  if (warnings.empty()) return "";
  std::ostringstream o;
  bool error = false;
  for (const Warning& w : warnings) error = error || w.error;
  o << "<section id=\"warnings\" class=\"warnings" << (error ? " error" : "") << "\">\n<h2>"
    << (warnings.size() == 1 ? "1 warning" : std::to_string(warnings.size()) + " warnings") << "</h2>\n<ul>\n";
  for (const Warning& w : warnings) {
    o << "<li>" << escapeHtml(w.message);
    if (!w.key.empty()) o << " <small>(run.json <code>" << escapeHtml(w.key) << "</code>)</small>";
    o << "</li>\n";
  }
  o << "</ul>\n</section>\n";
  return o.str();
}

std::string frameTime(const Run& run, int f) {
  return run.fps > 0 ? formatNumber(f / run.fps, 4) + " s" : "";
}

std::string filmSection(const Run& run) {
  std::ostringstream o;
  o << "<section id=\"film\">\n<h2>Film</h2>\n";
  if (run.film.empty() && run.pngs.empty() && run.status != "running") {
    o << "<p class=\"note\">No frames and no film in this folder: it was not rendered (<code>kurage sim</code> "
         "simulates only; <code>kurage surface</code> and <code>kurage render</code> on the same scene and OUT, or "
         "<code>kurage run</code>, make them).</p>\n</section>\n";
    return o.str();
  }
  if (!run.film.empty() && run.status != "running") {
    const int poster = run.pngs.empty() ? -1 : std::next(run.pngs.begin(), long(run.pngs.size() / 2))->first;
    // Shown at the film's size, within 320 to 960 pixels wide and at most 540 high.
    const double w = number(run.parameters(), {"render", "width"}, 960), h = number(run.parameters(), {"render", "height"}, 540);
    const int shownWidth = int(std::min({std::clamp(w, 320.0, 960.0), w > 0 && h > 0 ? 540.0 * w / h : 960.0}));
    o << "<video id=\"video\" controls preload=\"metadata\" style=\"width: " << shownWidth << "px\"";
    if (poster >= 0) o << " poster=\"" << urlPath(fs::relative(run.pngs.at(poster), run.out)) << "\"";
    o << "><source src=\"" << urlPath(run.film.filename()) << "\" type=\"video/mp4\"></video>\n"
      << "<p class=\"note\"><a href=\"" << urlPath(run.film.filename()) << "\">" << escapeHtml(run.film.filename().string())
      << "</a> · " << (run.frameCount ? std::to_string(run.frameCount) + " frames" : std::string()) << " at "
      << formatNumber(run.fps, 4) << " fps</p>\n";
  } else if (run.status == "running") {
    o << "<p class=\"note\">The film is made after the last frame; the frames rendered so far are below.</p>\n";
  } else {
    o << "<p class=\"note\">No film (" << escapeHtml(run.name()) << ".mp4): it is made from the PNG frames when ffmpeg is "
         "on the PATH, by <code>kurage run</code> and <code>kurage render</code> unless <code>--no-video</code>.</p>\n";
  }
  if (run.pngs.empty()) {
    o << "<p class=\"note\">No PNG frames in <code>frames/</code> yet.</p>\n";
  } else {
    // About 24 frames, evenly spaced, the last one included.
    const size_t n = run.pngs.size(), every = std::max<size_t>(1, (n + 23) / 24);
    o << "<h3>Contact sheet <small>(" << (every == 1 ? std::string("every frame") : "every " + std::to_string(every) + "th frame")
      << " of the " << n << " in <code>frames/</code>)</small></h3>\n<div class=\"sheet\">\n";
    size_t i = 0;
    for (const auto& [f, file] : run.pngs) {
      if (i++ % every != 0 && i != n) continue;
      const std::string url = urlPath(fs::relative(file, run.out));
      o << "<figure><a href=\"" << url << "\"><img src=\"" << url << "\" alt=\"frame " << f << "\"></a><figcaption>frame "
        << f << (run.fps > 0 ? " · " + frameTime(run, f) : "") << "</figcaption></figure>\n";
    }
    o << "</div>\n";
  }
  o << "</section>\n";
  return o.str();
}

// key = value pairs of an object's scalar members, for the brief.
std::string parameterList(const json& object) {
  std::ostringstream o;
  o << "<span class=\"params\">";
  bool first = true;
  for (const auto& [key, value] : object.items()) {
    if (value.is_object() || (value.is_array() && !value.empty() && value[0].is_object())) continue;
    o << (first ? "" : " ") << "<span><code>" << escapeHtml(key) << "</code> " << escapeHtml(shown(value)) << "</span>";
    first = false;
  }
  o << "</span>";
  return o.str();
}

std::string briefSection(const Run& run) {
  const json& p = run.parameters();
  const json& r = run.record;
  std::ostringstream o;
  o << "<section id=\"brief\">\n<h2>The run</h2>\n<table class=\"brief\">\n";
  const auto row = [&o](const std::string& name, const std::string& html) {
    if (!html.empty()) o << "<tr><th>" << escapeHtml(name) << "</th><td>" << html << "</td></tr>\n";
  };
  row("Scene", "<code>" + escapeHtml(text(r, {"scene_file"})) + "</code>");
  std::string command = text(r, {"command_line"});
  if (command.empty() && find(r, {"command"})) command = "kurage " + text(r, {"command"}) + " " + text(r, {"scene_file"});
  if (find(r, {"farm"})) command = "kurage farm (" + command + ")";
  row("Command", command.empty() ? "" : "<code>" + escapeHtml(command) + "</code>");
  if (run.frameCount)
    row("Frames", std::to_string(run.frameCount) + " at " + formatNumber(run.fps, 4) + " fps: " +
                      escapeHtml(formatNumber(number(p, {"output", "duration"}), 4)) + " s simulated");
  if (const json* sim = find(r, {"stages", "sim"})) {
    std::string particles = escapeHtml(shown((*sim).value("particles", json()))) + " at the end";
    if (double e = number(*sim, {"emitted_particles"}, 0); e > 0) particles += ", " + formatNumber(e, 9) + " emitted";
    if (double k = number(*sim, {"removed_by_sinks"}, 0); k > 0) particles += ", " + formatNumber(k, 9) + " removed by sinks";
    if (double b = number(*sim, {"bodies", "body_particles"}, 0); b > 0)
      particles += "; " + formatNumber(b, 9) + " of them in bodies, " + formatNumber(number(*sim, {"bodies", "springs"}, 0), 9) + " springs";
    row("Particles", particles);
  }
  if (const json* bodies = find(p, {"bodies"}); bodies && bodies->is_array() && !bodies->empty()) {
    std::string list;
    for (const json& b : *bodies) {
      list += list.empty() ? "" : ", ";
      list += "<b>" + escapeHtml(text(b, {"name"})) + "</b> (" + escapeHtml(text(b, {"shape"}));
      if (const json* muscles = find(b, {"muscles"}); muscles && muscles->is_array() && !muscles->empty()) {
        list += "; muscles:";
        for (const json& m : *muscles) list += " " + escapeHtml(text(m, {"name"}));
      }
      list += ")";
    }
    row("Bodies", list);
  }
  if (const json* fluid = find(p, {"fluid"}); fluid && fluid->is_object()) {
    std::string solver = "<b>" + escapeHtml(text(*fluid, {"solver"}, text(r, {"stages", "sim", "solver", "name"}))) + "</b>";
    if (std::string kernel = text(r, {"stages", "sim", "solver", "kernel"}); !kernel.empty()) solver += ", kernel " + escapeHtml(kernel);
    row("Solver", solver);
    row("Fluid", parameterList(*fluid));
  }
  if (const json* ts = find(p, {"time_step"}); ts && ts->is_object()) {
    std::string steps = parameterList(*ts);
    if (const json* sim = find(r, {"stages", "sim"})) {
      steps += "<br>" + escapeHtml(shown((*sim).value("steps", json()))) + " steps of " +
               escapeHtml(formatNumber(number(*sim, {"min_step_s"}), 3)) + " to " +
               escapeHtml(formatNumber(number(*sim, {"max_step_s"}), 3)) + " s";
      if (const json* bounds = find(*sim, {"active_bound_counts"}); bounds && bounds->is_object() && !bounds->empty()) {
        steps += ", limited by";
        for (const auto& [name, count] : bounds->items()) steps += " " + escapeHtml(name) + " (" + escapeHtml(shown(count)) + ")";
      }
    }
    row("Time step", steps);
  }
  if (const json* render = find(p, {"render"}); render && render->is_object()) {
    std::string line = escapeHtml(shown(render->value("width", json()))) + "×" + escapeHtml(shown(render->value("height", json()))) +
                       " pixels, " + escapeHtml(shown(render->value("samples", json()))) + " samples, depth " +
                       escapeHtml(shown(render->value("max_depth", json()))) + ", " + escapeHtml(text(*render, {"integrator"}));
    if (std::string quality = text(r, {"quality"}); !quality.empty()) line += "; quality " + escapeHtml(quality);
    row("Rendering", line);
  }
  if (const json* threads = find(r, {"threads"})) row("Threads", escapeHtml(shown(*threads)));
  if (const json* versions = find(r, {"versions"}); versions && versions->is_object()) {
    std::string list;
    for (const auto& [name, version] : versions->items())
      list += (list.empty() ? "" : " · ") + escapeHtml(name) + " " + escapeHtml(shown(version));
    row("Versions", list);
  }
  o << "</table>\n</section>\n";
  return o.str();
}

std::string timeSection(const Run& run) {
  const json* stages = find(run.record, {"stages"});
  if (!stages || !stages->is_object() || stages->empty()) return "";
  std::ostringstream o;
  o << "<section id=\"time\">\n<h2>Where the time went</h2>\n<div class=\"charts\">\n";
  std::vector<std::string> order{"sim", "surface", "render", "export"};
  for (const auto& [name, stage] : stages->items())
    if (std::find(order.begin(), order.end(), name) == order.end()) order.push_back(name);
  std::vector<SvgBar> bars;
  double total = 0.0;
  for (const std::string& name : order)
    if (double s = number(*stages, {name.c_str(), "seconds"}); std::isfinite(s)) {
      bars.push_back({name, s, ""});
      total += s;
    }
  for (SvgBar& b : bars)
    b.text = formatDuration(b.value) + (total > 0 ? " · " + formatPercent(b.value / total) : "");
  if (!bars.empty()) o << "<figure>" << svgBarChart("Seconds per stage (" + formatDuration(total) + " in all)", bars, "time-stages") << "</figure>\n";
  if (const json* steps = find(*stages, {"sim", "step_phases"}); steps && steps->is_object() && !steps->empty()) {
    std::vector<SvgBar> shares;
    for (const auto& [name, s] : steps->items())
      shares.push_back({name, number(s, {"share"}, 0.0),
                        formatPercent(number(s, {"share"}, 0.0)) + " · " + formatDuration(number(s, {"seconds"}, 0.0))});
    std::sort(shares.begin(), shares.end(), [](const SvgBar& a, const SvgBar& b) { return a.value > b.value; });
    o << "<figure>" << svgBarChart("The simulation's step phases (share of the step time)", shares, "time-step-phases") << "</figure>\n";
  }
  o << "</div>\n";
  if (const json* render = find(*stages, {"render"}); render && find(*render, {"total_mrays_per_s"}))
    o << "<p class=\"note\">Rendering traced " << escapeHtml(formatNumber(number(*render, {"total_rays"}) * 1e-6, 3)) << " million rays at "
      << escapeHtml(formatNumber(number(*render, {"total_mrays_per_s"}), 3)) << " Mrays/s.</p>\n";
  o << "</section>\n";
  return o.str();
}

Plot chart(const std::string& title, const std::string& yLabel) {
  Plot plot;
  plot.title = title;
  plot.x.label = "time (s)";
  plot.y.label = yLabel;
  plot.width = kChartWidth;
  plot.height = kChartHeight;
  return plot;
}

PlotSeries series(const std::string& label, const std::vector<double>& x, std::vector<double> y, bool markers) {
  PlotSeries s;
  s.label = label;
  s.x = x;
  s.y = std::move(y);
  s.markers = markers;
  s.markerSize = 0.9;
  return s;
}

// A log axis where positive values span more than a factor of 30.
bool spansDecades(const std::vector<double>& v) {
  double lo = INFINITY, hi = 0.0;
  for (double x : v)
    if (std::isfinite(x)) {
      if (x <= 0) return false;
      lo = std::min(lo, x), hi = std::max(hi, x);
    }
  return hi > 30 * lo;
}

std::string chartFigure(const Plot& plot, const std::string& id) { return "<figure>" + svgPlot(plot, id) + "</figure>\n"; }

std::string simulationSection(const Run& run) {
  if (!run.frames) return "";
  const CsvTable& t = *run.frames;
  const std::vector<double> time = t.numbers("time_s");
  const bool markers = time.size() <= 60;
  std::ostringstream o;
  o << "<section id=\"simulation\">\n<h2>The simulation over time</h2>\n<p class=\"note\">Per frame, from "
    << "<a href=\"sim_frames.csv\">sim_frames.csv</a>: each value is over the steps since the frame before.</p>\n"
    << "<div class=\"charts\">\n";
  {
    Plot p = chart("Time step", "mean step (s)");
    p.series.push_back(series("mean step", time, t.numbers("mean_step_s"), markers));
    p.y.log = spansDecades(p.series.back().y);
    p.legend = false;
    o << chartFigure(p, "sim-step");
  }
  std::vector<std::string> solves;
  for (const std::string& c : t.header)
    if (c.size() > 20 && c.compare(c.size() - 20, 20, "_iterations_per_step") == 0) solves.push_back(c.substr(0, c.size() - 20));
  if (!solves.empty()) {
    Plot p = chart("Pressure solver iterations", "iterations per step");
    PlotSeries caps = series("stopped at the cap", {}, {}, true);
    caps.lines = false;
    caps.colour = Eigen::Vector3f(0.85f, 0.1f, 0.1f);
    caps.markerSize = 1.5;
    for (const std::string& s : solves) {
      p.series.push_back(series(s + " solve", time, t.numbers(s + "_iterations_per_step"), markers));
      if (t.has(s + "_cap_hits")) {
        const std::vector<double> hits = t.numbers(s + "_cap_hits");
        for (size_t i = 0; i < hits.size(); ++i)
          if (hits[i] > 0) caps.x.push_back(time[i]), caps.y.push_back(p.series.back().y[i]);
      }
    }
    if (!caps.x.empty()) p.series.push_back(std::move(caps));
    p.y.min = 0.0;
    o << chartFigure(p, "sim-iterations");
  }
  {
    Plot p = chart("Density error", "mean compression (% of rest density)");
    std::vector<double> e = t.numbers("mean_density_error");
    for (double& v : e) v *= 100.0;
    p.series.push_back(series("measured", time, e, markers));
    const double tolerance = number(run.parameters(), {"fluid", "max_density_error"});
    if (!solves.empty() && std::isfinite(tolerance) && !time.empty()) {
      PlotSeries line = series("fluid.max_density_error", {time.front(), time.back()}, {tolerance, tolerance}, false);
      line.colour = Eigen::Vector3f(0.5f, 0.5f, 0.5f);
      line.lineWidth = 1.0;
      p.series.push_back(std::move(line));
    } else {
      p.legend = false;
    }
    p.y.min = 0.0;
    o << chartFigure(p, "sim-density-error");
  }
  {
    Plot p = chart("Particles", "particles");
    p.series.push_back(series("particles", time, t.numbers("particles"), markers));
    p.legend = false;
    o << chartFigure(p, "sim-particles");
  }
  {
    Plot p = chart("Kinetic energy", "kinetic energy (J)");
    p.series.push_back(series("kinetic energy", time, t.numbers("kinetic_energy_J"), markers));
    p.legend = false;
    p.y.min = 0.0;
    o << chartFigure(p, "sim-kinetic-energy");
  }
  // Caps hit per frame, where any was.
  {
    Plot p = chart("Caps hit", "steps stopped at a cap");
    for (const std::string& c : t.header)
      if (c.size() > 9 && c.compare(c.size() - 9, 9, "_cap_hits") == 0) {
        const std::vector<double> hits = t.numbers(c);
        if (std::any_of(hits.begin(), hits.end(), [](double h) { return h > 0; }))
          p.series.push_back(series(c.substr(0, c.size() - 9), time, hits, markers));
      }
    p.y.min = 0.0;
    if (!p.series.empty()) o << chartFigure(p, "sim-caps");
  }
  o << "</div>\n</section>\n";
  return o.str();
}

std::string bodiesSection(const Run& run) {
  const json* bodies = find(run.parameters(), {"bodies"});
  if (!run.bodies || !bodies || !bodies->is_array() || bodies->empty()) return "";
  const CsvTable& t = *run.bodies;
  const std::vector<double> time = t.numbers("time_s");
  const bool markers = time.size() <= 60;
  std::vector<std::string> names, shells;
  std::vector<std::pair<std::string, std::string>> muscles;  // label, column
  for (const json& b : *bodies) {
    const std::string name = text(b, {"name"});
    names.push_back(name);
    if (text(b, {"shape"}) == "shell") shells.push_back(name);
    if (const json* list = find(b, {"muscles"}); list && list->is_array())
      for (const json& m : *list) muscles.push_back({name + " " + text(m, {"name"}), name + "_" + text(m, {"name"}) + "_force_N"});
  }
  // One series per body (or shell) whose column exists.
  const auto perBody = [&](Plot& p, const std::vector<std::string>& of, const std::string& suffix, double scale = 1.0) {
    for (const std::string& name : of)
      if (t.has(name + suffix)) {
        std::vector<double> y = t.numbers(name + suffix);
        for (double& v : y) v *= scale;
        p.series.push_back(series(name, time, y, markers));
      }
    p.legend = p.series.size() > 1;
  };
  std::ostringstream o;
  o << "<section id=\"bodies\">\n<h2>The bodies over time</h2>\n<p class=\"note\">Per frame, from "
    << "<a href=\"bodies.csv\">bodies.csv</a>.</p>\n<div class=\"charts\">\n";
  if (!muscles.empty()) {
    // The paper's Fig. 3: the muscles' force and the bodies' depth below the free surface.
    Plot p = chart("Muscle force and depth (as the paper's Fig. 3)", "depth below the surface (m)");
    p.y2.label = "force per spring (N)";
    perBody(p, names, "_depth_m");
    for (PlotSeries& s : p.series) s.label += " depth";
    for (const auto& [label, column] : muscles)
      if (t.has(column)) {
        p.series.push_back(series(label + " force", time, t.numbers(column), false));
        p.series.back().axis = 1;
        p.series.back().lineWidth = 1.5;
      }
    p.legend = true;
    o << chartFigure(p, "bodies-fig3");
  } else {
    Plot p = chart("Depth below the surface", "depth (m)");
    perBody(p, names, "_depth_m");
    o << chartFigure(p, "bodies-depth");
  }
  {
    Plot p = chart("Rest-density factor", "rest density / initial");
    perBody(p, names, "_rest_density_factor");
    o << chartFigure(p, "bodies-rest-density");
  }
  if (!shells.empty()) {
    const struct {
      const char* title;
      const char* axis;
      const char* suffix;
      const char* id;
    } shellCharts[] = {{"Tilt", "tilt from the axis as built (°)", "_tilt_deg", "bodies-tilt"},
                       {"Margin radius", "margin radius (m)", "_margin_radius_m", "bodies-margin"},
                       {"Apex height (swimming)", "height of the apex (m)", "_apex_z_m", "bodies-apex"},
                       {"Diameter", "diameter (m)", "_diameter_m", "bodies-diameter"},
                       {"Fluid inside the wall", "fluid particles", "_fluid_in_wall", "bodies-in-wall"}};
    for (const auto& c : shellCharts) {
      Plot p = chart(c.title, c.axis);
      perBody(p, shells, c.suffix);
      if (!p.series.empty()) o << chartFigure(p, c.id);
    }
  }
  o << "</div>\n";
  // The shells' summaries from run.json, the swim figures among them.
  if (const json* list = find(run.record, {"stages", "sim", "bodies", "bodies"}); list && list->is_array()) {
    std::ostringstream rows;
    for (const json& b : *list) {
      const json* shell = find(b, {"shell"});
      if (!shell) continue;
      rows << "<tr><th>" << escapeHtml(text(b, {"name"})) << "</th><td>"
           << escapeHtml(formatNumber(number(*shell, {"margin_radius_at_rest_m"}), 3)) << " → "
           << escapeHtml(formatNumber(number(*shell, {"margin_radius_min_m"}), 3)) << " m</td><td>"
           << escapeHtml(formatNumber(number(*shell, {"fluid_inside_wall_max"}), 6)) << "</td><td>";
      if (const json* swim = find(*shell, {"swim"}))
        rows << escapeHtml(formatNumber(number(*swim, {"bell_diameters_per_pulse"}), 3)) << " bell diameters a pulse ("
             << escapeHtml(formatNumber(number(*swim, {"apex_rise_m"}), 3)) << " m over "
             << escapeHtml(formatNumber(number(*swim, {"pulses"}), 3)) << " pulses)";
      else
        rows << "no whole pulse recorded";
      rows << "</td></tr>\n";
    }
    if (!rows.str().empty())
      o << "<table class=\"data\"><tr><th>shell</th><th>margin radius, at rest → smallest</th><th>most fluid particles "
           "inside the wall</th><th>swimming</th></tr>\n"
        << rows.str() << "</table>\n";
  }
  o << "</section>\n";
  return o.str();
}

std::string outputsSection(const Run& run) {
  struct Output {
    fs::path path;
    const char* what;
    const char* opens;
  };
  const std::string film = run.name() + ".mp4";
  const Output outputs[] = {
      {film, "the film (H.264)", "any video player, a browser, this page"},
      {"frames", "frames (PNG; EXR with layers where render.outputs asks)", "any image viewer; EXR: Nuke, Blender's compositor, <code>exrheader</code>"},
      {"particles", "particle caches (OpenVDB point grids: <code>v</code>, <code>id</code>, <code>kind</code>)", "Houdini, <code>vdb_print -l</code>; <code>kurage export</code> for Blender and ParaView"},
      {"surfaces", "surfaces (OpenVDB level sets, one grid per material)", "Blender (a volume sequence), Houdini, <code>vdb_view</code>"},
      {"exports", "exports (PLY, OBJ, VTP)", "Blender (<code>assets/blender/import_kurage.py</code>), ParaView, MeshLab"},
      {"preview", "the OpenGL preview", "any image or video player"},
      {"run.json", "the run's record: parameters in effect, versions, per-stage figures", "a text editor, <code>jq</code>"},
      {"sim_frames.csv", "the simulation per frame (this page's plots)", "a spreadsheet, pandas, gnuplot"},
      {"bodies.csv", "the bodies per frame", "a spreadsheet, pandas, gnuplot"},
      {"bodies.png", "the muscles' force and the bodies' depth (with .svg, .pdf, and .gp for gnuplot)", "<code>gnuplot bodies.gp</code> redraws it"},
      {"checkpoint.bin", "the simulation's newest checkpoint", "<code>kurage sim|run ... --resume</code>"},
      {"farm", "Slurm job scripts and logs", "<code>kurage farm status OUT</code>"},
      {"records", "the farm tasks' records", "<code>kurage farm merge OUT</code> assembles run.json"},
  };
  std::ostringstream o;
  o << "<section id=\"outputs\">\n<h2>Outputs</h2>\n<table class=\"data\">\n<tr><th>in OUT</th><th>what</th><th>size</th><th>opens with</th></tr>\n";
  for (const Output& out : outputs) {
    const fs::path path = run.out / out.path;
    std::error_code ec;
    if (!fs::exists(path, ec)) continue;
    std::string size;
    if (fs::is_directory(path, ec)) {
      const FolderSize s = folderSize(path);
      size = std::to_string(s.files) + " files, " + bytesText(s.bytes);
    } else {
      size = bytesText(fs::file_size(path, ec));
    }
    const std::string name = out.path.string() + (fs::is_directory(path, ec) ? "/" : "");
    o << "<tr><td><a href=\"" << urlPath(out.path) << "\"><code>" << escapeHtml(name) << "</code></a></td><td>" << out.what
      << "</td><td>" << escapeHtml(size) << "</td><td>" << out.opens << "</td></tr>\n";
  }
  o << "</table>\n</section>\n";
  return o.str();
}

std::string runPage(const Run& run) {
  const bool running = run.status == "running";
  PageHead head;
  head.title = run.name() + " · kurage";
  head.refresh = running;
  // A frame can take long: the page says the run may have stopped only well past the time a
  // frame has taken so far.
  if (running && run.live && run.live->done > 0)
    head.quietSeconds = std::max(60.0, 5.0 * run.live->seconds / run.live->done);
  std::ostringstream o;
  o << pageStart(head);
  o << "<header>\n<h1>" << escapeHtml(run.name()) << "</h1>\n";
  if (std::string d = text(run.parameters(), {"description"}); !d.empty()) o << "<p class=\"lead\">" << escapeHtml(d) << "</p>\n";
  o << statusLine(run) << "</header>\n";
  o << warningsBox(warningsOf(run));
  o << filmSection(run) << briefSection(run) << timeSection(run) << simulationSection(run) << bodiesSection(run)
    << outputsSection(run);
  o << pageEnd(head, "kurage report " + shellWord(run.out.string(), false), "redraws it");
  return o.str();
}

}  // namespace

std::string runReportHtml(const fs::path& outDir, const std::optional<ProgressState>& live) {
  const Run run = readRun(outDir, live);
  try {
    return runPage(run);
  } catch (const json::exception& e) {
    throw std::runtime_error((outDir / "run.json").string() + ": damaged, a value of the wrong type (" + e.what() + ")");
  }
}

void writeRunReport(const fs::path& outDir, const std::optional<ProgressState>& live) {
  writeTextAtomic(outDir / "report.html", runReportHtml(outDir, live));
}

LiveRunReport::LiveRunReport(fs::path outDir, double intervalSeconds)
    : outDir_(std::move(outDir)), interval_(intervalSeconds) {}

ProgressObserver LiveRunReport::observer() {
  return [this](const ProgressState& state) { update(state); };
}

void LiveRunReport::update(const ProgressState& state) {
  const auto now = std::chrono::steady_clock::now();
  const bool edge = state.done == 0 || state.done >= state.total;
  if (!edge && written_ && std::chrono::duration<double>(now - last_).count() < interval_) return;
  write(state);
}

void LiveRunReport::finish() { write(std::nullopt); }

void LiveRunReport::write(const std::optional<ProgressState>& state) {
  last_ = std::chrono::steady_clock::now();
  written_ = true;
  try {
    writeRunReport(outDir_, state);
  } catch (const std::exception& e) {
    std::cerr << "kurage: warning: the report page was not updated: " << e.what() << "\n";
  }
}

}  // namespace kurage::pipeline
