#include "pipeline/report/html.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>

namespace kurage::pipeline {

std::string escapeHtml(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (char c : text) switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&#39;"; break;
      default: out += c;
    }
  return out;
}

std::string urlPath(const std::filesystem::path& relative) {
  static const char* hex = "0123456789ABCDEF";
  std::string out;
  for (const auto& part : relative) {
    if (!out.empty()) out += '/';
    for (unsigned char c : part.string()) {
      if (std::isalnum(c) || c == '-' || c == '.' || c == '_' || c == '~') {
        out += char(c);
      } else {
        out += '%';
        out += hex[c >> 4];
        out += hex[c & 15];
      }
    }
  }
  return out;
}

std::string formatNumber(double value, int digits) {
  if (!std::isfinite(value)) return "";
  char buffer[48];
  std::snprintf(buffer, sizeof buffer, "%.*g", digits, value);
  std::string s = buffer;
  const size_t e = s.find('e');
  if (e != std::string::npos) {  // e-05 -> e-5, e+06 -> e6
    std::string mantissa = s.substr(0, e), exponent = s.substr(e + 1);
    const bool negative = exponent[0] == '-';
    exponent.erase(0, exponent.find_first_not_of("+-"));
    exponent.erase(0, std::min(exponent.find_first_not_of('0'), exponent.size() - 1));
    s = mantissa + "e" + (negative ? "-" : "") + exponent;
  }
  return s;
}

namespace {
// Two significant digits below 10, whole numbers from 10 on ("0.42", "4.1", "12", "150").
std::string twoDigits(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, v < 10 ? "%.2g" : "%.0f", v);
  return buffer;
}
}  // namespace

std::string formatDuration(double seconds) {
  if (!std::isfinite(seconds) || seconds < 0) return "";
  if (seconds == 0) return "0 s";
  if (seconds < 1e-3) return twoDigits(seconds * 1e6) + " µs";
  if (seconds < 1) return seconds < 0.01 ? twoDigits(seconds * 1e3) + " ms" : twoDigits(seconds) + " s";
  char buffer[48];
  if (seconds < 10) std::snprintf(buffer, sizeof buffer, "%.2g s", seconds);
  else if (seconds < 60) std::snprintf(buffer, sizeof buffer, "%.1f s", seconds);
  else if (seconds < 3600) {
    const long s = std::lround(seconds);
    std::snprintf(buffer, sizeof buffer, "%ld min %02ld s", s / 60, s % 60);
  } else {
    const long m = std::lround(seconds / 60);
    std::snprintf(buffer, sizeof buffer, "%ld h %02ld min", m / 60, m % 60);
  }
  return buffer;
}

std::string formatPercent(double fraction) {
  if (!std::isfinite(fraction)) return "";
  return twoDigits(100.0 * fraction) + " %";
}

}  // namespace kurage::pipeline
