// JSON from files, bounded: the nesting depth is checked on the raw text before nlohmann's parser
// sees it (its parser and serializer recurse once per level, and a path kept per level costs the
// square of the depth), and values go into messages as excerpts of bounded length, never dumped
// whole. Scenes and studies are parsed strictly by
// pipeline::parseStrictJson (pipeline/scene.h), which applies the same depth limit.
#pragma once

#include <nlohmann/json.hpp>

#include <cstddef>
#include <filesystem>
#include <string>
#include <string_view>

namespace kurage::pipeline {

// Scenes nest 4 levels, studies and run records 6: 64 leaves room for anything a person writes.
inline constexpr int kMaxJsonDepth = 64;
// A scene, study or record is parameters, not data.
inline constexpr size_t kMaxJsonBytes = size_t(16) << 20;

// The byte offset of the first '[' or '{' (outside strings) that opens a level deeper than
// `maxDepth`; std::string_view::npos when there is none. Linear in the text, no allocation.
size_t jsonDepthBeyond(std::string_view text, int maxDepth = kMaxJsonDepth);

// "line L, column C" of a byte offset, for messages.
std::string lineAndColumn(std::string_view text, size_t offset);

// Reads and parses a JSON file kurage wrote (OUT/run.json, farm records and plans). Throws IoError
// naming the file when it cannot be read, is larger than kMaxJsonBytes, nests deeper than
// kMaxJsonDepth or is not valid JSON (with the line and column).
nlohmann::json readJson(const std::filesystem::path& file);

// `value` as JSON text of at most about `limit` bytes: longer strings, arrays and objects are cut
// with "..." and their full size. Never recurses deeper than the value's own nesting.
std::string jsonExcerpt(const nlohmann::json& value, size_t limit = 80);

// `text` cut to at most `limit` bytes (on a UTF-8 boundary), "... (N bytes)" appended when cut.
std::string textExcerpt(std::string_view text, size_t limit = 80);

}  // namespace kurage::pipeline
