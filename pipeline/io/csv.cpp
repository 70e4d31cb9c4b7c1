#include "pipeline/io/csv.h"

#include <cmath>
#include <cstdlib>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace kurage::pipeline {

std::string csvField(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string out = "\"";
  for (char c : s) out += c == '"' ? std::string("\"\"") : std::string(1, c == '\n' ? ' ' : c);
  return out + "\"";
}

std::vector<std::string> csvRecord(const std::string& line) {
  std::vector<std::string> fields(1);
  bool quoted = false;
  for (size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quoted) {
      if (c == '"' && i + 1 < line.size() && line[i + 1] == '"') fields.back() += '"', ++i;
      else if (c == '"') quoted = false;
      else fields.back() += c;
    } else if (c == '"') {
      quoted = true;
    } else if (c == ',') {
      fields.emplace_back();
    } else {
      fields.back() += c;
    }
  }
  return fields;
}

std::optional<size_t> CsvTable::column(const std::string& name) const {
  for (size_t i = 0; i < header.size(); ++i)
    if (header[i] == name) return i;
  return std::nullopt;
}

std::vector<double> CsvTable::numbers(const std::string& name) const {
  const std::optional<size_t> c = column(name);
  if (!c) throw std::runtime_error(file + ": no column '" + name + "'");
  std::vector<double> values;
  values.reserve(rows.size());
  for (size_t r = 0; r < rows.size(); ++r) {
    const std::string& field = rows[r][*c];
    if (field.empty()) {
      values.push_back(std::numeric_limits<double>::quiet_NaN());
      continue;
    }
    char* end = nullptr;
    const double v = std::strtod(field.c_str(), &end);
    if (end != field.c_str() + field.size())
      throw std::runtime_error(file + ": line " + std::to_string(r + 2) + ", column '" + name + "': '" + field +
                               "' is not a number");
    values.push_back(v);
  }
  return values;
}

CsvTable parseCsvTable(const std::string& text, const std::string& file) {
  CsvTable table;
  table.file = file;
  std::istringstream in(text);
  std::string line;
  if (!std::getline(in, line) || line.empty()) throw std::runtime_error(file + ": empty, no header line");
  table.header = csvRecord(line);
  for (size_t number = 2; std::getline(in, line); ++number) {
    if (line.empty()) continue;
    std::vector<std::string> fields = csvRecord(line);
    if (fields.size() != table.header.size())
      throw std::runtime_error(file + ": line " + std::to_string(number) + " has " + std::to_string(fields.size()) +
                               " fields, the header " + std::to_string(table.header.size()));
    table.rows.push_back(std::move(fields));
  }
  return table;
}

}  // namespace kurage::pipeline
