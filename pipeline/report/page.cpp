#include "pipeline/report/page.h"

#include "pipeline/report/html.h"

#include <chrono>
#include <ctime>

namespace kurage::pipeline {

namespace {

const char* const kStyle = R"(
:root { color-scheme: light; }
body { margin: 0; font: 15px/1.5 system-ui, -apple-system, "Segoe UI", sans-serif; color: #222; background: #f5f5f2; }
main { max-width: 1180px; margin: 0 auto; padding: 20px 28px 40px; }
h1 { font-size: 28px; margin: 0 0 2px; }
h2 { font-size: 19px; margin: 30px 0 10px; padding-bottom: 4px; border-bottom: 1px solid #ddd; }
h3 { font-size: 15px; margin: 18px 0 8px; }
h3 small, h2 small { font-weight: normal; color: #666; }
a { color: #1a5fb4; }
.lead { color: #555; margin: 0 0 8px; max-width: 75em; }
.note { color: #666; font-size: 14px; }
.status { margin: 8px 0; }
.pill { display: inline-block; padding: 1px 10px; border-radius: 10px; font-size: 12px; font-weight: 700;
        letter-spacing: .05em; text-transform: uppercase; color: #fff; background: #777; }
.complete .pill { background: #2a7d3f; } .running .pill { background: #2f63c9; }
.failed .pill { background: #b3261e; } .interrupted .pill { background: #a86b00; }
progress { width: 220px; vertical-align: middle; }
ol.stages { list-style: none; padding: 0; margin: 6px 0; display: flex; flex-wrap: wrap; gap: 6px; }
ol.stages li { padding: 1px 10px; border-radius: 4px; font-size: 13px; background: #e6e6e3; color: #666; }
ol.stages li.done { background: #d8eedc; color: #1d5a2c; } ol.stages li.running { background: #d9e4fa; color: #1e3f86; font-weight: 600; }
.quiet { background: #eee; border-radius: 6px; padding: 6px 12px; }
.warnings { background: #fff7df; border: 1px solid #e2b203; border-left-width: 6px; border-radius: 6px; padding: 2px 18px 6px; margin: 16px 0; }
.warnings.error { background: #fdeceb; border-color: #b3261e; }
.warnings h2 { border: 0; margin: 8px 0 0; padding: 0; font-size: 17px; }
.warnings ul { margin: 6px 0; padding-left: 20px; }
video { display: block; max-width: 100%; background: #000; border-radius: 4px; }
.sheet { display: grid; grid-template-columns: repeat(auto-fill, minmax(150px, 1fr)); gap: 10px; }
.sheet figure { margin: 0; padding: 4px; background: #fff; border: 1px solid #ddd; border-radius: 4px; }
.sheet img { display: block; width: 100%; height: auto; }
.sheet figcaption { font-size: 12px; color: #555; text-align: center; }
table { border-collapse: collapse; background: #fff; }
table.brief { width: 100%; border: 1px solid #ddd; }
table.brief tr { border-bottom: 1px solid #eee; }
table.brief th { text-align: left; vertical-align: top; padding: 6px 18px 6px 12px; color: #555; white-space: nowrap; }
table.brief td { padding: 6px 12px; }
.params > span { display: inline-block; margin: 0 16px 2px 0; }
code { font: 13px ui-monospace, "DejaVu Sans Mono", monospace; background: #efefec; padding: 0 3px; border-radius: 3px; }
table.data th, table.data td { border: 1px solid #ddd; padding: 4px 10px; text-align: left; vertical-align: top; font-size: 14px; }
table.data th { background: #f0f0ed; }
tr.failed td { background: #fdeceb; } tr.pending td { color: #888; }
.charts { display: grid; grid-template-columns: repeat(auto-fill, minmax(470px, 1fr)); gap: 16px; align-items: start; }
.charts + table { margin-top: 16px; }
.charts figure { margin: 0; padding: 8px; background: #fff; border: 1px solid #ddd; border-radius: 6px; }
.charts svg { display: block; width: 100%; height: auto; }
figure.wide { margin: 0; max-width: 980px; padding: 8px; background: #fff; border: 1px solid #ddd; border-radius: 6px; }
figure.wide svg { display: block; width: 100%; height: auto; }
footer { margin-top: 36px; color: #888; font-size: 13px; }
)";

std::string utcNow() {
  const std::time_t now = std::time(nullptr);
  std::tm utc{};
  gmtime_r(&now, &utc);
  char buffer[40];
  std::strftime(buffer, sizeof buffer, "%Y-%m-%d %H:%M:%S UTC", &utc);
  return buffer;
}

}  // namespace

std::string pageStart(const PageHead& head) {
  std::string s = "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
                  "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n"
                  "<meta name=\"generator\" content=\"kurage\">\n" +
                  std::string(head.refresh ? "<meta http-equiv=\"refresh\" content=\"5\">\n" : "") + "<title>" +
                  escapeHtml(head.title) + "</title>\n<style>" + kStyle + "</style>\n</head>\n<body>\n<main>\n";
  if (head.refresh) s += "<p id=\"quiet\" class=\"quiet\" hidden></p>\n";
  return s;
}

std::string pageEnd(const PageHead& head, const std::string& command, const std::string& what) {
  std::string s = "<footer>Written by kurage at " + utcNow() + (head.refresh ? ", while the work goes on" : "") +
                  "; <code>" + escapeHtml(command) + "</code> " + escapeHtml(what) + ".</footer>\n</main>\n";
  if (head.refresh) {
    const long long written = std::chrono::duration_cast<std::chrono::milliseconds>(
                                  std::chrono::system_clock::now().time_since_epoch()).count();
    s += "<script>\n(function () {\n  var written = " + std::to_string(written) +
         ", quiet = " + std::to_string(static_cast<long long>(head.quietSeconds * 1000.0)) +
         ";\n"
         "  try { var y = sessionStorage.getItem('kurage-scroll'); if (y !== null) window.scrollTo(0, +y); } catch (e) {}\n"
         "  var age = Date.now() - written, note = document.getElementById('quiet');\n"
         "  if (age > quiet && note) {\n"
         "    note.hidden = false;\n"
         "    note.textContent = 'No news for ' + Math.round(age / 60000) + ' min: the work may have stopped. '\n"
         "      + 'The page reloads while it waits.';\n"
         "  }\n"
         "  window.addEventListener('pagehide', function () {\n"
         "    try { sessionStorage.setItem('kurage-scroll', String(window.scrollY)); } catch (e) {}\n"
         "  });\n"
         "})();\n</script>\n";
  }
  s += "</body>\n</html>\n";
  return s;
}

}  // namespace kurage::pipeline
