// A simulation's state as bytes, for checkpoints (pipeline/io/checkpoint.h writes them to a
// file; sim/ knows no files). Values are written in the machine's own representation: a
// checkpoint is read back by the same kurage build on the same kind of machine, which the
// checkpoint's header checks. Restoring it continues the run bit for bit (docs/design/reliability.md).
#pragma once

#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

namespace kurage::sim {

// Thrown for state bytes that do not fit: truncated, or sizes that disagree with the scene.
class StateError : public std::runtime_error {
public:
  using std::runtime_error::runtime_error;
};

class StateWriter {
public:
  template <class T>
  void value(const T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    bytes_.append(reinterpret_cast<const char*>(&v), sizeof(T));
  }
  template <class T>
  void array(const std::vector<T>& v) {
    value(uint64_t(v.size()));
    if (!v.empty()) bytes_.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
  }
  const std::string& bytes() const { return bytes_; }
  std::string take() { return std::move(bytes_); }

private:
  std::string bytes_;
};

class StateReader {
public:
  explicit StateReader(std::string_view bytes) : bytes_(bytes) {}
  template <class T>
  T value() {
    static_assert(std::is_trivially_copyable_v<T>);
    T v;
    std::memcpy(&v, take(sizeof(T)), sizeof(T));
    return v;
  }
  // An array of at most `maxCount` elements (a size beyond it is damage, not an allocation).
  template <class T>
  void array(std::vector<T>& v, uint64_t maxCount) {
    const uint64_t n = value<uint64_t>();
    if (n > maxCount || n * sizeof(T) > bytes_.size() - offset_)
      throw StateError("checkpoint state: an array of " + std::to_string(n) + " elements does not fit");
    v.resize(size_t(n));
    if (n) std::memcpy(v.data(), take(size_t(n) * sizeof(T)), size_t(n) * sizeof(T));
  }
  // An array that must have exactly `count` elements.
  template <class T>
  void arrayOf(std::vector<T>& v, uint64_t count) {
    array(v, count);
    if (v.size() != count)
      throw StateError("checkpoint state: " + std::to_string(v.size()) + " elements where the scene has " +
                       std::to_string(count));
  }
  bool done() const { return offset_ == bytes_.size(); }

private:
  const char* take(size_t n) {
    if (n > bytes_.size() - offset_) throw StateError("checkpoint state: truncated");
    const char* p = bytes_.data() + offset_;
    offset_ += n;
    return p;
  }
  std::string_view bytes_;
  size_t offset_ = 0;
};

}  // namespace kurage::sim
