#include "pipeline/io/plot.h"

#include "pipeline/io/files.h"
#include "pipeline/io/process.h"

#include <cmath>
#include <cstdio>
#include <sstream>
#include <stdexcept>

namespace kurage::pipeline {

namespace fs = std::filesystem;

namespace {

// A gnuplot double-quoted string.
std::string gnuplotString(const std::string& text) {
  std::string out = "\"";
  for (char c : text) {
    if (c == '"' || c == '\\') out.push_back('\\');
    if (c == '\n') {
      out += "\\n";
      continue;
    }
    out.push_back(c);
  }
  return out + "\"";
}

// A string column of an inline data block (gnuplot reads "..." as one column; no escapes there).
std::string dataString(const std::string& text) {
  std::string out = "\"";
  for (char c : text) out.push_back(c == '"' ? '\'' : c == '\n' ? ' ' : c);
  return out + "\"";
}

std::string number(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.6g", v);  // as study.csv keeps them
  return buffer;
}

std::string colourHex(const Eigen::Vector3f& c) {
  char buffer[16];
  auto byte = [](float v) { return int(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f)); };
  std::snprintf(buffer, sizeof buffer, "#%02x%02x%02x", byte(c.x()), byte(c.y()), byte(c.z()));
  return buffer;
}

void axis(std::ostringstream& s, const char* name, const PlotAxis& a) {
  if (!a.label.empty()) s << "set " << name << "label " << gnuplotString(a.label) << " noenhanced\n";
  if (a.log) s << "set logscale " << name << "\n";
  if (std::isfinite(a.min) || std::isfinite(a.max))
    s << "set " << name << "range [" << (std::isfinite(a.min) ? number(a.min) : "*") << ":"
      << (std::isfinite(a.max) ? number(a.max) : "*") << "]\n";
}

std::string fileString(const fs::path& p) { return gnuplotString(p.string()); }

}  // namespace

std::vector<std::string> wrapTitle(const std::string& title, size_t maxCharacters) {
  std::vector<std::string> lines;
  std::istringstream words(title);
  std::string word, line;
  while (words >> word) {
    if (!line.empty() && line.size() + 1 + word.size() > maxCharacters) {
      lines.push_back(line);
      line.clear();
    }
    line += (line.empty() ? "" : " ") + word;
  }
  if (!line.empty()) lines.push_back(line);
  return lines;
}

std::string gnuplotScript(const Plot& plot, const PlotOutputs& outputs) {
  std::ostringstream s;
  s << "# kurage figure: `gnuplot THIS_FILE` redraws the PNG, SVG and PDF beside it.\n"
    << "set encoding utf8\nreset\n";
  // About 7 pixels a character at the 11-point font of the PNG.
  std::string title;
  for (const std::string& line : wrapTitle(plot.title, size_t(std::max(20, int(plot.width / (8 * plot.scale))))))
    title += (title.empty() ? "" : "\n") + line;
  if (!title.empty()) s << "set title " << gnuplotString(title) << " noenhanced\n";
  bool right = false;
  for (const PlotSeries& series : plot.series) right = right || series.axis == 1;
  axis(s, "x", plot.x);
  axis(s, "y", plot.y);
  if (right) {
    axis(s, "y2", plot.y2);
    s << "set ytics nomirror\nset y2tics\n";
  }
  // Room around the data, so that points on the range's ends and their labels stay inside.
  s << "set offsets graph 0.03, graph 0.12, graph 0.06, graph 0.06\n";
  if (plot.grid) s << "set grid xtics ytics mxtics mytics lc rgb \"#dddddd\" lw 1, lc rgb \"#f0f0f0\" lw 1\n";
  s << (plot.legend ? "set key below noenhanced\n" : "unset key\n");

  // Data blocks: x y label; a skipped point is a blank line, which breaks the series' line.
  for (size_t k = 0; k < plot.series.size(); ++k) {
    const PlotSeries& series = plot.series[k];
    const bool logY = series.axis == 1 ? plot.y2.log : plot.y.log;
    s << "$series" << k << " << EOD\n";
    const size_t n = std::min(series.x.size(), series.y.size());
    for (size_t i = 0; i < n; ++i) {
      const double x = series.x[i], y = series.y[i];
      if (!std::isfinite(x) || !std::isfinite(y) || (plot.x.log && x <= 0) || (logY && y <= 0)) {
        s << "\n";
        continue;
      }
      s << number(x) << " " << number(y) << " "
        << dataString(i < series.pointLabels.size() ? series.pointLabels[i] : "") << "\n";
    }
    s << "EOD\n";
  }
  std::ostringstream plotCommand;
  plotCommand << "plot ";
  bool first = true;
  for (size_t k = 0; k < plot.series.size(); ++k) {
    const PlotSeries& series = plot.series[k];
    const std::string axes = series.axis == 1 ? " axes x1y2" : " axes x1y1";
    const std::string colour = std::isfinite(series.colour.x()) ? " lc rgb \"" + colourHex(series.colour) + "\"" : " lc " + std::to_string(k + 1);
    const char* style = series.lines && series.markers ? "linespoints" : series.markers ? "points" : "lines";
    // gnuplot's default colours repeat after eight: each round of them gets its own filled marker
    // (circle, square, triangle, diamond), so that no two series look alike.
    static constexpr int kMarkers[] = {7, 5, 9, 13};
    const int marker = kMarkers[(k / 8) % 4];
    plotCommand << (first ? "" : ", \\\n     ") << "$series" << k << " using 1:2 with " << style << colour << " lw "
                << number(series.lineWidth) << " pt " << marker << " ps " << number(series.markerSize) << axes << " title "
                << (series.label.empty() ? "\"\"" : gnuplotString(series.label)) << " noenhanced";
    first = false;
    bool labelled = false;
    for (const std::string& l : series.pointLabels) labelled = labelled || !l.empty();
    if (labelled)
      plotCommand << ", \\\n     $series" << k << " using 1:2:3 with labels left offset 0.8,0.4 font \",9\" tc rgb \"#333333\""
                  << axes << " notitle noenhanced";
  }
  if (first) {  // an empty figure still has its axes and title
    s << "set xrange [0:1]\nset yrange [0:1]\n";
    plotCommand << "NaN notitle";
  }
  const double inchesW = plot.width / 100.0, inchesH = plot.height / 100.0;
  // (gnuplot's svg terminal has no pointscale: its markers keep their size)
  const std::string svgScaled =
      plot.scale == 1.0 ? std::string() : " fontscale " + number(plot.scale) + " linewidth " + number(plot.scale);
  const std::string scaled = plot.scale == 1.0 ? std::string() : svgScaled + " pointscale " + number(plot.scale);
  s << "set terminal pngcairo size " << plot.width << "," << plot.height << " font \"sans,11\"" << scaled << "\n"
    << "set output " << fileString(outputs.png) << "\n"
    << plotCommand.str() << "\n"
    << "set terminal svg size " << plot.width << "," << plot.height << " font \"sans,11\"" << svgScaled << "\n"
    << "set output " << fileString(outputs.svg) << "\nreplot\n"
    << "set terminal pdfcairo size " << number(inchesW) << "in," << number(inchesH) << "in font \"sans,8\"" << scaled
    << "\n"
    << "set output " << fileString(outputs.pdf) << "\nreplot\nunset output\n";
  return s.str();
}

void writePlot(const Plot& plot, const fs::path& png) {
  const fs::path base = fs::path(png).replace_extension();
  const PlotOutputs finals{base.string() + ".png", base.string() + ".svg", base.string() + ".pdf"};
  // FILE.gp names its outputs relative to its own folder, so it redraws wherever it is moved.
  const PlotOutputs relative{finals.png.filename(), finals.svg.filename(), finals.pdf.filename()};
  writeTextAtomic(base.string() + ".gp", gnuplotScript(plot, relative));
  if (std::system("command -v gnuplot > /dev/null 2>&1") != 0) {
    std::fprintf(stderr, "kurage: warning: gnuplot not found; %s.gp draws the figure (apt-get install gnuplot-nox)\n",
                 base.string().c_str());
    return;
  }
  // gnuplot draws into unique temporaries (pipeline/io/files.h), committed only when it succeeded,
  // from a script in a temporary of its own; it dies with kurage (process.h).
  TempFile pngFile(finals.png), svgFile(finals.svg), pdfFile(finals.pdf), script(base.string() + ".gp");
  script.write(gnuplotScript(plot, {pngFile.path(), svgFile.path(), pdfFile.path()}));
  std::string log;
  if (runProgram({"gnuplot", script.path().string()}, &log) != 0)
    throw IoError(finals.png.string() + ": gnuplot failed: " + log);
  pngFile.commit();
  svgFile.commit();
  pdfFile.commit();
}

}  // namespace kurage::pipeline
