// Text in HTML and SVG: escaping and relative links, for the report pages.
#pragma once

#include <filesystem>
#include <string>

namespace kurage::pipeline {

// Text or an attribute value, with & < > " ' as character references (HTML and XML alike).
std::string escapeHtml(const std::string& text);

// A relative path as a URL path: each of its parts percent-encoded except unreserved characters
// (RFC 3986), so a name with spaces, '#' or '?' still links to its file.
std::string urlPath(const std::filesystem::path& relative);

// A number with `digits` significant digits ("%.*g"), an exponent as "e-5" not "e-05"; an empty
// string for a value that is not finite.
std::string formatNumber(double value, int digits = 3);

// Seconds as "22 µs", "4.1 ms", "0.42 s", "12.3 s", "4 min 05 s", "2 h 07 min".
std::string formatDuration(double seconds);

// A fraction as a percentage: "0.42 %", "8.3 %", "73 %", "100 %".
std::string formatPercent(double fraction);

}  // namespace kurage::pipeline
