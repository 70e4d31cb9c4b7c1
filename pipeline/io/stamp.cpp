#include "pipeline/io/stamp.h"

#include "pipeline/io/files.h"

#include <algorithm>
#include <cstring>

namespace kurage::pipeline {

namespace {

// OpenVDB serialises a string metadata entry as: u32 length, name, u32 length, type name
// ("string"), u32 value size, value (little-endian on every platform we build for).
std::string checksumEntryPrefix() {
  std::string prefix;
  const auto u32 = [&prefix](uint32_t v) {
    for (int b = 0; b < 4; ++b) prefix.push_back(char((v >> (8 * b)) & 0xff));
  };
  const std::string_view name = "kurage:checksum", type = "string";
  u32(uint32_t(name.size()));
  prefix += name;
  u32(uint32_t(type.size()));
  prefix += type;
  u32(uint32_t(kChecksumPlaceholder.size()));
  return prefix;
}

// The offset of the checksum's 16 digits, or npos. File metadata precede the grids, so the first
// occurrence is the file's own entry.
size_t findChecksum(const std::string& bytes) {
  static const std::string prefix = checksumEntryPrefix();
  const size_t at = bytes.find(prefix);
  if (at == std::string::npos || at + prefix.size() + kChecksumPlaceholder.size() > bytes.size()) return std::string::npos;
  return at + prefix.size();
}

uint64_t checksumOf(const std::string& bytes, size_t digits) {
  uint64_t h = fnv1a64(std::string_view(bytes.data(), digits));
  h = fnv1a64(kChecksumPlaceholder, h);
  const size_t rest = digits + kChecksumPlaceholder.size();
  return fnv1a64(std::string_view(bytes.data() + rest, bytes.size() - rest), h);
}

}  // namespace

std::string checksumField() { return checksumEntryPrefix() + std::string(kChecksumPlaceholder); }

uint64_t fnv1a64(std::string_view bytes, uint64_t hash) {
  for (const char c : bytes) {
    hash ^= uint64_t(static_cast<unsigned char>(c));
    hash *= 0x100000001b3ull;
  }
  return hash;
}

std::string hex64(uint64_t value) {
  static const char digits[] = "0123456789abcdef";
  std::string out(16, '0');
  for (int i = 15; i >= 0; --i, value >>= 4) out[size_t(i)] = digits[value & 0xf];
  return out;
}

void sealChecksum(std::string& bytes, const std::filesystem::path& path) {
  const size_t at = findChecksum(bytes);
  if (at == std::string::npos || bytes.compare(at, kChecksumPlaceholder.size(), kChecksumPlaceholder) != 0)
    throw IoError(path.string() + ": internal error: no kurage:checksum placeholder in the serialised file");
  const std::string sum = hex64(checksumOf(bytes, at));
  std::copy(sum.begin(), sum.end(), bytes.begin() + long(at));
}

void verifyChecksum(const std::string& bytes, const std::filesystem::path& path) {
  const size_t at = findChecksum(bytes);
  if (at == std::string::npos)
    throw IoError(path.string() + ": not a kurage file (no kurage:checksum; empty, truncated at the start, or made "
                                  "by another program or an older kurage)");
  const std::string stored = bytes.substr(at, kChecksumPlaceholder.size());
  const uint64_t sum = checksumOf(bytes, at);
  // The stored digits are compared as a number, not as text: a string comparison hands its
  // operands to comparison-guided fuzzers (libFuzzer splices the expected digits into the next
  // input), which then feed OpenVDB's parser files with forged checksums; damaged files are the
  // promise here, and a forged file is outside it (tests/fuzz/README.md).
  uint64_t value = 0;
  bool digits = true;
  for (const char c : stored) {
    const int d = c >= '0' && c <= '9' ? c - '0' : c >= 'a' && c <= 'f' ? c - 'a' + 10 : -1;
    digits = digits && d >= 0;
    value = value << 4 | uint64_t(d & 0xf);
  }
  if (!digits || (value ^ sum) != 0) {
    const std::string actual = hex64(sum);
    throw IoError(path.string() + ": damaged or truncated (checksum " + actual + ", the file says " + stored + ", " +
                  std::to_string(bytes.size()) + " bytes)");
  }
}

std::string stampText(const FileStamp& stamp) {
  return stamp.stage + " " + stamp.sceneHash + " " + std::to_string(stamp.frame);
}

void checkStamp(const FileStamp& found, const FileStamp& expected, const std::filesystem::path& path) {
  if (!expected.stage.empty() && found.stage != expected.stage)
    throw IoError(path.string() + ": wrong kind of file: made by the '" + found.stage + "' stage, expected '" +
                  expected.stage + "'");
  if (expected.frame >= 0 && found.frame != expected.frame)
    throw IoError(path.string() + ": holds frame " + std::to_string(found.frame) + ", expected frame " +
                  std::to_string(expected.frame));
  if (!expected.sceneHash.empty() && found.sceneHash != expected.sceneHash)
    throw IoError(path.string() + ": made from other scene parameters (scene hash " + found.sceneHash +
                  ", this scene's is " + expected.sceneHash + "); run the stage that makes it again");
}

}  // namespace kurage::pipeline

namespace kurage::pipeline {

void writeSealed(const std::filesystem::path& path, std::string bytes) {
  sealChecksum(bytes, path);
  writeFileAtomic(path, bytes);
}

std::string readVerified(const std::filesystem::path& path) {
  std::string bytes = readFile(path);
  verifyChecksum(bytes, path);
  return bytes;
}

}  // namespace kurage::pipeline
