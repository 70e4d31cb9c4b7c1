#include "pipeline/io/image_file.h"

#include "pipeline/io/files.h"

#include <array>
#include <cstdint>

namespace kurage::pipeline {

namespace {

constexpr std::string_view kPngSignature{"\x89PNG\r\n\x1a\n", 8};
constexpr std::string_view kStampKey{"kurage:stamp"};

// CRC-32 of PNG chunks (ISO 3309, polynomial 0xEDB88320; PNG specification, annex D).
uint32_t crc32(std::string_view bytes) {
  static const std::array<uint32_t, 256> table = [] {
    std::array<uint32_t, 256> t{};
    for (uint32_t n = 0; n < 256; ++n) {
      uint32_t c = n;
      for (int k = 0; k < 8; ++k) c = (c & 1u) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
      t[n] = c;
    }
    return t;
  }();
  uint32_t c = 0xFFFFFFFFu;
  for (unsigned char b : bytes) c = table[(c ^ b) & 0xFFu] ^ (c >> 8);
  return c ^ 0xFFFFFFFFu;
}

void putBigEndian(std::string& out, uint32_t v) {
  for (int shift = 24; shift >= 0; shift -= 8) out += char((v >> shift) & 0xFFu);
}

uint32_t getBigEndian(std::string_view bytes, size_t at) {
  uint32_t v = 0;
  for (size_t i = 0; i < 4; ++i) v = (v << 8) | uint32_t(static_cast<unsigned char>(bytes[at + i]));
  return v;
}

}  // namespace

void writePng(const render::Image& image, const std::filesystem::path& path, bool withAlpha, int bitDepth,
              const FileStamp* stamp) {
  std::string bytes;
  try {
    bytes = render::encodePng(image, withAlpha, bitDepth);
  } catch (const std::exception& e) {
    throw IoError(path.string() + ": " + e.what());
  }
  if (stamp) {
    // After the signature (8 bytes) and IHDR (4 length + 4 type + 13 data + 4 CRC).
    const size_t afterHeader = kPngSignature.size() + 25;
    std::string data = std::string(kStampKey) + '\0' + stampText(*stamp);
    std::string chunk;
    putBigEndian(chunk, uint32_t(data.size()));
    const std::string typed = "tEXt" + data;
    chunk += typed;
    putBigEndian(chunk, crc32(typed));
    bytes.insert(afterHeader, chunk);
  }
  writeFileAtomic(path, bytes);
}

bool pngStampMatches(const std::filesystem::path& path, const FileStamp& expected) {
  std::string bytes;
  try {
    bytes = readFile(path);
  } catch (const IoError&) {
    return false;  // missing, unreadable or not a regular file: redo it
  }
  if (bytes.compare(0, kPngSignature.size(), kPngSignature) != 0) return false;
  bool stamped = false;
  for (size_t at = kPngSignature.size();;) {
    if (at + 12 > bytes.size()) return false;  // truncated
    const uint32_t length = getBigEndian(bytes, at);
    if (length > bytes.size() - at - 12) return false;
    const std::string_view typed(bytes.data() + at + 4, size_t(length) + 4);
    if (crc32(typed) != getBigEndian(bytes, at + 8 + length)) return false;
    const std::string_view type = typed.substr(0, 4), data = typed.substr(4);
    if (type == "tEXt" && data.substr(0, kStampKey.size() + 1) == std::string(kStampKey) + '\0')
      stamped = data.substr(kStampKey.size() + 1) == stampText(expected);
    at += 12 + size_t(length);
    if (type == "IEND") return stamped && at == bytes.size();
  }
}

}  // namespace kurage::pipeline
