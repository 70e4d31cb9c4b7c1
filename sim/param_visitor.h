// The parameter registry's vocabulary, for parameters that sim/ declares itself (a pressure
// solver's, sim/solvers/): a field's unit, documentation and valid range, and an abstract visitor
// that a parameter struct's describe() calls once per field. The pipeline's strict JSON reader,
// its JSON writer and its schema writer implement the visitor (pipeline/param_visitor.h), so a
// solver's keys are loaded, written to run.json and put in scenes/schema.json like every other
// parameter, while sim/ knows nothing of JSON.
#pragma once

#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace kurage::sim {

struct Range {
  std::optional<double> min, max;
  bool minExclusive = false, maxExclusive = false;
};
inline Range positive() { return {0.0, std::nullopt, true, false}; }
inline Range nonNegative() { return {0.0, std::nullopt, false, false}; }
inline Range atLeast(double v) { return {v, std::nullopt, false, false}; }
inline Range between(double a, double b) { return {a, b, false, false}; }
inline Range anyValue() { return {}; }

struct Field {
  const char* unit = "";  // SI unit, or "" for dimensionless
  const char* doc = "";
  Range range = {};
  bool required = false;
};

// An enumeration's names (strings in a scene, never integers) and values.
template <class E>
using EnumTable = std::vector<std::pair<const char*, E>>;

class ParamVisitor {
public:
  virtual ~ParamVisitor() = default;
  virtual void value(const char* key, float& ref, const Field& f) = 0;
  virtual void value(const char* key, int& ref, const Field& f) = 0;
  virtual void value(const char* key, bool& ref, const Field& f) = 0;
  // An enumeration, as the index of its value in `names`.
  virtual void choice(const char* key, size_t& index, const std::vector<const char*>& names, const Field& f) = 0;

  template <class E>
  void enumeration(const char* key, E& ref, const EnumTable<E>& table, const Field& f) {
    std::vector<const char*> names;
    size_t index = 0;
    for (size_t k = 0; k < table.size(); ++k) {
      names.push_back(table[k].first);
      if (table[k].second == ref) index = k;
    }
    choice(key, index, names, f);
    ref = table[index].second;
  }
};

}  // namespace kurage::sim
