// The parameter registry's vocabulary: a field's unit, documentation and valid range, and the
// visitors that walk a parameter struct's describe() function. One describe() per component
// (pipeline/scene_params.h) drives three visitors:
//   JsonReader   strict loading: unknown keys, wrong types, missing required values and values
//                out of range are errors naming the file and the JSON path
//   JsonWriter   the parameters in effect after defaults (run.json)
//   SchemaWriter the JSON Schema of scenes (scenes/schema.json), defaults taken from the structs
// so the loader, the schema and the defaults cannot drift apart.
#pragma once

#include "pipeline/io/json_file.h"
#include "sim/param_visitor.h"

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include <cmath>
#include <optional>
#include <set>
#include <type_traits>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace kurage::pipeline {

// A scene error: names the file and the JSON path, e.g.
//   scenes/dam_break.json: fluid.spacing: must be > 0, got -3
class SceneError : public std::runtime_error {
public:
  SceneError(std::string file, std::string jsonPath, std::string message);
  const std::string& file() const { return file_; }
  const std::string& jsonPath() const { return path_; }
  const std::string& message() const { return message_; }

private:
  std::string file_, path_, message_;
};

// The vocabulary is sim/'s (sim/param_visitor.h), so that sim/ can declare parameters of its own.
using sim::anyValue;
using sim::atLeast;
using sim::between;
using sim::EnumTable;
using sim::Field;
using sim::nonNegative;
using sim::positive;
using sim::Range;

// The shortest decimal that reads back as the same float, as a double (0.3f -> 0.3), so that
// JSON output shows the numbers a user wrote.
double tidyFloat(float v);

// ---------------------------------------------------------------------------------------------
// Strict reader.
class JsonReader {
public:
  JsonReader(const nlohmann::json& object, std::string file, std::string path);

  void value(const char* key, float& ref, const Field& f) { number(key, ref, f, false); }
  void value(const char* key, double& ref, const Field& f) { number(key, ref, f, false); }
  void value(const char* key, int& ref, const Field& f) { number(key, ref, f, true); }
  void value(const char* key, bool& ref, const Field& f);
  void value(const char* key, std::string& ref, const Field& f);
  void value(const char* key, Eigen::Vector3f& ref, const Field& f);
  // Any JSON value, taken as it is (the caller checks it; study knob values, for instance).
  void value(const char* key, nlohmann::json& ref, const Field& f);

  template <class E>
  void enumeration(const char* key, E& ref, const EnumTable<E>& table, const Field& f) {
    const nlohmann::json* j = find(key, f);
    if (!j) return;
    if (j->is_string()) {
      for (const auto& [name, e] : table)
        if (*j == name) { ref = e; return; }
    }
    std::string names;
    for (const auto& [name, e] : table) names += (names.empty() ? "\"" : ", \"") + std::string(name) + "\"";
    fail(key, "must be one of " + names + ", got " + jsonExcerpt(*j));
  }

  template <class T>
  void object(const char* key, T& ref, const Field& f) {
    const nlohmann::json* j = find(key, f);
    if (!j) return;
    if (!j->is_object()) fail(key, "must be an object, got " + jsonExcerpt(*j));
    JsonReader child(*j, file_, childPath(key));
    describe(child, ref);
    child.finish();
  }

  template <class T>
  void list(const char* key, std::vector<T>& ref, const Field& f) {
    const nlohmann::json* j = find(key, f);
    if (!j) return;
    if (!j->is_array()) fail(key, "must be an array, got " + jsonExcerpt(*j));
    ref.clear();
    for (size_t i = 0; i < j->size(); ++i) {
      const std::string itemPath = childPath(key) + "[" + std::to_string(i) + "]";
      if (!(*j)[i].is_object()) throw SceneError(file_, itemPath, "must be an object, got " + jsonExcerpt((*j)[i]));
      T item{};
      JsonReader child((*j)[i], file_, itemPath);
      describe(child, item);
      child.finish();
      ref.push_back(std::move(item));
    }
  }

  // Keys that are allowed but carry no parameter (e.g. "$schema").
  void ignore(const char* key) { seen_.insert(key); }

  // Refuses every key that no describe() call asked for.
  void finish() const;

  [[noreturn]] void fail(const std::string& key, const std::string& message) const;
  std::string childPath(const std::string& key) const { return path_.empty() ? key : path_ + "." + key; }
  const std::string& file() const { return file_; }

private:
  const nlohmann::json* find(const char* key, const Field& f);
  template <class T>
  void number(const char* key, T& ref, const Field& f, bool integral);
  void checkRange(const char* key, double v, const Range& r) const;
  void checkFloat(const char* key, double v) const;

  const nlohmann::json& object_;
  std::string file_, path_;
  std::set<std::string> seen_;
};

// ---------------------------------------------------------------------------------------------
// Writes values as JSON (parameters in effect).
class JsonWriter {
public:
  explicit JsonWriter(nlohmann::json& out) : out_(out) { out_ = nlohmann::json::object(); }
  template <class T>
  void value(const char* key, const T& ref, const Field&) { out_[key] = ref; }
  void value(const char* key, const float& ref, const Field&) { out_[key] = tidyFloat(ref); }
  void value(const char* key, const Eigen::Vector3f& ref, const Field&) {
    out_[key] = {tidyFloat(ref.x()), tidyFloat(ref.y()), tidyFloat(ref.z())};
  }
  template <class E>
  void enumeration(const char* key, const E& ref, const EnumTable<E>& table, const Field&) {
    for (const auto& [name, e] : table)
      if (e == ref) out_[key] = name;
  }
  template <class T>
  void object(const char* key, T& ref, const Field&) {
    JsonWriter child(out_[key]);
    describe(child, ref);
  }
  template <class T>
  void list(const char* key, std::vector<T>& ref, const Field&) {
    nlohmann::json array = nlohmann::json::array();
    for (T& item : ref) {
      nlohmann::json j;
      JsonWriter child(j);
      describe(child, item);
      array.push_back(std::move(j));
    }
    out_[key] = std::move(array);
  }
  void ignore(const char*) {}

private:
  nlohmann::json& out_;
};

// ---------------------------------------------------------------------------------------------
// Writes the JSON Schema (draft 2020-12) of a describe() function; defaults are the struct's.
class SchemaWriter {
public:
  explicit SchemaWriter(nlohmann::json& out);
  void value(const char* key, const float& ref, const Field& f) { numberSchema(key, ref, f, "number"); }
  void value(const char* key, const double& ref, const Field& f) { numberSchema(key, ref, f, "number"); }
  void value(const char* key, const int& ref, const Field& f) { numberSchema(key, ref, f, "integer"); }
  void value(const char* key, const bool& ref, const Field& f);
  void value(const char* key, const std::string& ref, const Field& f);
  void value(const char* key, const Eigen::Vector3f& ref, const Field& f);
  template <class E>
  void enumeration(const char* key, const E& ref, const EnumTable<E>& table, const Field& f) {
    nlohmann::json s = base(f);
    s["type"] = "string";
    s["enum"] = nlohmann::json::array();
    for (const auto& [name, e] : table) {
      s["enum"].push_back(name);
      if (e == ref) s["default"] = name;
    }
    add(key, std::move(s), f);
  }
  template <class T>
  void object(const char* key, T& ref, const Field& f) {
    nlohmann::json s;
    SchemaWriter child(s);
    describe(child, ref);
    s["description"] = f.doc;
    add(key, std::move(s), f);
  }
  template <class T>
  void list(const char* key, std::vector<T>&, const Field& f) {
    nlohmann::json item;
    T prototype{};
    SchemaWriter child(item);
    describe(child, prototype);
    nlohmann::json s = base(f);
    s["type"] = "array";
    s["items"] = std::move(item);
    add(key, std::move(s), f);
  }
  void ignore(const char* key);

private:
  nlohmann::json base(const Field& f) const;
  void add(const char* key, nlohmann::json schema, const Field& f);
  template <class T>
  void numberSchema(const char* key, T ref, const Field& f, const char* type) {
    nlohmann::json s = base(f);
    s["type"] = type;
    if constexpr (std::is_same_v<T, float>) s["default"] = tidyFloat(ref);
    else s["default"] = ref;
    if (f.range.min) s[f.range.minExclusive ? "exclusiveMinimum" : "minimum"] = *f.range.min;
    if (f.range.max) s[f.range.maxExclusive ? "exclusiveMaximum" : "maximum"] = *f.range.max;
    add(key, std::move(s), f);
  }

  nlohmann::json& out_;
};

// ---------------------------------------------------------------------------------------------
// One of the visitors above as sim::ParamVisitor, for the parameters sim/ declares (a pressure
// solver's describe(), sim/solvers/).
template <class V>
class SimParamVisitor final : public sim::ParamVisitor {
public:
  explicit SimParamVisitor(V& visitor) : v_(visitor) {}
  void value(const char* key, float& ref, const Field& f) override { v_.value(key, ref, f); }
  void value(const char* key, int& ref, const Field& f) override { v_.value(key, ref, f); }
  void value(const char* key, bool& ref, const Field& f) override { v_.value(key, ref, f); }
  void choice(const char* key, size_t& index, const std::vector<const char*>& names, const Field& f) override {
    EnumTable<size_t> table;
    for (size_t k = 0; k < names.size(); ++k) table.emplace_back(names[k], k);
    v_.enumeration(key, index, table, f);
  }

private:
  V& v_;
};

}  // namespace kurage::pipeline
