#include "pipeline/param_visitor.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>
#include <sstream>
#include <type_traits>

namespace kurage::pipeline {

namespace {
double tidy(float v) {
  char buffer[32];
  auto [end, ec] = std::to_chars(buffer, buffer + sizeof buffer, v);
  (void)ec;
  return std::stod(std::string(buffer, end));
}

std::string formatNumber(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

size_t editDistance(const std::string& a, const std::string& b) {
  std::vector<size_t> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    size_t diagonal = row[0];
    row[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = up;
    }
  }
  return row[b.size()];
}
}  // namespace

// Paths and messages are cut to a bounded length: they may carry text from the file (a key, a
// name) of any size.
SceneError::SceneError(std::string file, std::string jsonPath, std::string message)
    : std::runtime_error(file + ": " + (jsonPath.empty() ? std::string("(top level)") : textExcerpt(jsonPath, 200)) +
                         ": " + textExcerpt(message, 2000)),
      file_(std::move(file)), path_(textExcerpt(jsonPath, 200)), message_(textExcerpt(message, 2000)) {}

JsonReader::JsonReader(const nlohmann::json& object, std::string file, std::string path)
    : object_(object), file_(std::move(file)), path_(std::move(path)) {}

void JsonReader::fail(const std::string& key, const std::string& message) const {
  throw SceneError(file_, childPath(key), message);
}

const nlohmann::json* JsonReader::find(const char* key, const Field& f) {
  seen_.insert(key);
  const auto it = object_.find(key);
  if (it == object_.end()) {
    if (f.required) fail(key, "is required but missing");
    return nullptr;
  }
  return &*it;
}

void JsonReader::checkRange(const char* key, double v, const Range& r) const {
  if (!std::isfinite(v)) fail(key, "must be a finite number, got " + formatNumber(v));
  if (r.min && (r.minExclusive ? !(v > *r.min) : !(v >= *r.min)))
    fail(key, std::string("must be ") + (r.minExclusive ? "> " : ">= ") + formatNumber(*r.min) + ", got " +
                  formatNumber(v));
  if (r.max && (r.maxExclusive ? !(v < *r.max) : !(v <= *r.max)))
    fail(key, std::string("must be ") + (r.maxExclusive ? "< " : "<= ") + formatNumber(*r.max) + ", got " +
                  formatNumber(v));
}

void JsonReader::checkFloat(const char* key, double v) const {
  // Values are kept as 32-bit floats: one beyond their range would become infinite, a tiny one 0.
  if (std::abs(v) > double(std::numeric_limits<float>::max()))
    fail(key, "is beyond the range of a 32-bit float (about 3.4e38), got " + formatNumber(v));
  if (v != 0.0 && std::abs(v) < double(std::numeric_limits<float>::min()))
    fail(key, "is too small for a 32-bit float (below about 1.2e-38), got " + formatNumber(v));
}

template <class T>
void JsonReader::number(const char* key, T& ref, const Field& f, bool integral) {
  const nlohmann::json* j = find(key, f);
  if (!j) return;
  if (!j->is_number()) fail(key, std::string("must be ") + (integral ? "an integer" : "a number") + ", got " + jsonExcerpt(*j));
  const double v = j->get<double>();
  if (integral && (!j->is_number_integer() || v < std::numeric_limits<int>::min() || v > std::numeric_limits<int>::max()))
    fail(key, "must be an integer, got " + jsonExcerpt(*j));
  checkRange(key, v, f.range);
  if constexpr (std::is_same_v<T, float>) checkFloat(key, v);
  ref = static_cast<T>(v);
}
template void JsonReader::number<float>(const char*, float&, const Field&, bool);
template void JsonReader::number<double>(const char*, double&, const Field&, bool);
template void JsonReader::number<int>(const char*, int&, const Field&, bool);

void JsonReader::value(const char* key, bool& ref, const Field& f) {
  const nlohmann::json* j = find(key, f);
  if (!j) return;
  if (!j->is_boolean()) fail(key, "must be true or false, got " + jsonExcerpt(*j));
  ref = j->get<bool>();
}

void JsonReader::value(const char* key, std::string& ref, const Field& f) {
  const nlohmann::json* j = find(key, f);
  if (!j) return;
  if (!j->is_string()) fail(key, "must be a string, got " + jsonExcerpt(*j));
  ref = j->get<std::string>();
}

void JsonReader::value(const char* key, nlohmann::json& ref, const Field& f) {
  if (const nlohmann::json* j = find(key, f)) ref = *j;
}

void JsonReader::value(const char* key, Eigen::Vector3f& ref, const Field& f) {
  const nlohmann::json* j = find(key, f);
  if (!j) return;
  if (!j->is_array() || j->size() != 3) fail(key, "must be an array of 3 numbers, got " + jsonExcerpt(*j));
  for (int a = 0; a < 3; ++a) {
    const nlohmann::json& c = (*j)[size_t(a)];
    const std::string itemKey = std::string(key) + "[" + std::to_string(a) + "]";
    if (!c.is_number()) fail(itemKey, "must be a number, got " + jsonExcerpt(c));
    checkRange(itemKey.c_str(), c.get<double>(), f.range);
    checkFloat(itemKey.c_str(), c.get<double>());
    ref[a] = c.get<float>();
  }
}

void JsonReader::finish() const {
  for (const auto& [key, value] : object_.items()) {
    if (seen_.count(key)) continue;
    std::string hint;
    size_t best = 3;
    for (const std::string& known : seen_) {
      if (key.size() > known.size() + best) continue;  // also keeps a megabyte-long key from costing seconds
      const size_t d = editDistance(key, known);
      if (d < best) { best = d; hint = " (did you mean \"" + known + "\"?)"; }
    }
    fail(key, "unknown key" + hint);
  }
}

// ---------------------------------------------------------------------------------------------

SchemaWriter::SchemaWriter(nlohmann::json& out) : out_(out) {
  out_ = nlohmann::json::object();
  out_["type"] = "object";
  out_["additionalProperties"] = false;
  out_["properties"] = nlohmann::json::object();
}

nlohmann::json SchemaWriter::base(const Field& f) const {
  nlohmann::json s = nlohmann::json::object();
  std::string doc = f.doc;
  if (f.unit && *f.unit) doc += std::string(" [") + f.unit + "]";
  s["description"] = doc;
  return s;
}

void SchemaWriter::add(const char* key, nlohmann::json schema, const Field& f) {
  nlohmann::json& properties = out_["properties"];
  if (properties.contains(key)) {
    // A key two pressure solvers declare (sim::SolverParams): one type, range and default, both docs.
    nlohmann::json& known = properties[key];
    nlohmann::json a = known, b = schema;
    a.erase("description");
    b.erase("description");
    if (a != b)
      throw std::logic_error(std::string("schema: two declarations of \"") + key + "\" differ in type, range or default");
    known["description"] = known["description"].get<std::string>() + "; " + schema["description"].get<std::string>();
    return;
  }
  properties[key] = std::move(schema);
  if (f.required) out_["required"].push_back(key);
}

void SchemaWriter::value(const char* key, const bool& ref, const Field& f) {
  nlohmann::json s = base(f);
  s["type"] = "boolean";
  s["default"] = ref;
  add(key, std::move(s), f);
}

void SchemaWriter::value(const char* key, const std::string& ref, const Field& f) {
  nlohmann::json s = base(f);
  s["type"] = "string";
  s["default"] = ref;
  add(key, std::move(s), f);
}

void SchemaWriter::value(const char* key, const Eigen::Vector3f& ref, const Field& f) {
  nlohmann::json s = base(f);
  s["type"] = "array";
  s["minItems"] = 3;
  s["maxItems"] = 3;
  nlohmann::json item = {{"type", "number"}};
  if (f.range.min) item[f.range.minExclusive ? "exclusiveMinimum" : "minimum"] = *f.range.min;
  if (f.range.max) item[f.range.maxExclusive ? "exclusiveMaximum" : "maximum"] = *f.range.max;
  s["items"] = item;
  s["default"] = {tidy(ref.x()), tidy(ref.y()), tidy(ref.z())};
  add(key, std::move(s), f);
}

void SchemaWriter::ignore(const char* key) { out_["properties"][key] = {{"type", "string"}}; }

double tidyFloat(float v) { return tidy(v); }

}  // namespace kurage::pipeline
