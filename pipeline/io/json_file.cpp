#include "pipeline/io/json_file.h"

#include "pipeline/io/files.h"

namespace kurage::pipeline {

namespace {

using Json = nlohmann::json;

// The longest prefix of `text` of at most `bytes` bytes that ends on a UTF-8 character boundary.
std::string_view utf8Prefix(std::string_view text, size_t bytes) {
  if (bytes >= text.size()) return text;
  while (bytes > 0 && (static_cast<unsigned char>(text[bytes]) & 0xC0) == 0x80) --bytes;
  return text.substr(0, bytes);
}

std::string jsonString(std::string_view text) {
  return Json(std::string(text)).dump(-1, ' ', false, Json::error_handler_t::replace);
}

// Nesting beyond this is shown as [...] or {...}: the excerpt is short anyway.
constexpr int kExcerptDepth = 8;

void appendExcerpt(const Json& value, std::string& out, size_t limit, int depth) {
  const size_t room = limit > out.size() ? limit - out.size() : 0;
  switch (value.type()) {
    case Json::value_t::string: {
      const std::string& s = value.get_ref<const std::string&>();
      if (s.size() <= room) {
        out += jsonString(s);
      } else {
        out += jsonString(utf8Prefix(s, room));
        out += "... (" + std::to_string(s.size()) + " bytes)";
      }
      return;
    }
    case Json::value_t::array:
    case Json::value_t::object: {
      const bool array = value.is_array();
      if (depth >= kExcerptDepth) {
        out += array ? "[...]" : "{...}";
        return;
      }
      out += array ? '[' : '{';
      size_t i = 0;
      for (auto it = value.begin(); it != value.end(); ++it, ++i) {
        if (out.size() >= limit) {
          out += "... (" + std::to_string(value.size()) + (array ? " items)" : " keys)");
          break;
        }
        if (i > 0) out += ", ";
        if (!array) out += jsonString(utf8Prefix(it.key(), 40)) + ": ";
        appendExcerpt(*it, out, limit, depth + 1);
      }
      out += array ? ']' : '}';
      return;
    }
    default: out += value.dump(); return;
  }
}

}  // namespace

size_t jsonDepthBeyond(std::string_view text, int maxDepth) {
  int depth = 0;
  bool inString = false, escaped = false;
  for (size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (inString) {
      if (escaped) escaped = false;
      else if (c == '\\') escaped = true;
      else if (c == '"') inString = false;
    } else if (c == '"') {
      inString = true;
    } else if (c == '[' || c == '{') {
      if (++depth > maxDepth) return i;
    } else if ((c == ']' || c == '}') && depth > 0) {
      --depth;
    }
  }
  return std::string_view::npos;
}

std::string lineAndColumn(std::string_view text, size_t offset) {
  size_t line = 1, column = 1;
  for (size_t i = 0; i < offset && i < text.size(); ++i) {
    if (text[i] == '\n') {
      ++line;
      column = 1;
    } else {
      ++column;
    }
  }
  return "line " + std::to_string(line) + ", column " + std::to_string(column);
}

nlohmann::json readJson(const std::filesystem::path& file) {
  const std::string text = readFile(file, kMaxJsonBytes);
  if (const size_t at = jsonDepthBeyond(text); at != std::string_view::npos)
    throw IoError(file.string() + ": nested deeper than " + std::to_string(kMaxJsonDepth) + " levels at " +
                  lineAndColumn(text, at));
  try {
    return nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {
    throw IoError(file.string() + ": not valid JSON (damaged or cut short?): " + e.what());
  }
}

std::string jsonExcerpt(const nlohmann::json& value, size_t limit) {
  std::string out;
  appendExcerpt(value, out, limit, 0);
  return out;
}

std::string textExcerpt(std::string_view text, size_t limit) {
  if (text.size() <= limit) return std::string(text);
  return std::string(utf8Prefix(text, limit)) + "... (" + std::to_string(text.size()) + " bytes)";
}

}  // namespace kurage::pipeline
