// Files that cannot lie: every particle cache and surface file kurage writes is an OpenVDB file
// whose file metadata carries
//   kurage:stage       string  "sim" (particle cache) or "surface" (level sets)
//   kurage:scene_hash  string  16 hex digits: the hash of the scene parameters that made the file
//                              (inputsHash in pipeline/io/scene_hash.h; per stage)
//   kurage:frame       int32   the output frame
//   kurage:checksum    string  16 hex digits: FNV-1a 64 of the whole file with these 16 digits
//                              read as '0'
// The checksum is sealed into the serialised bytes before they are written, and readers check it
// on the raw bytes before OpenVDB's parser sees them: a truncated or damaged file is an error
// naming the file, never a crash inside OpenVDB. The stage, scene hash and frame are checked
// after parsing (the bytes are then known to be intact). The files stay plain OpenVDB files.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

namespace kurage::pipeline {

// What a file must say it is. An empty sceneHash or stage, or a frame < 0, is not checked.
struct FileStamp {
  std::string stage;
  std::string sceneHash;
  int frame = -1;
};

// The metadata value to write for kurage:checksum before sealing (16 '0').
inline constexpr std::string_view kChecksumPlaceholder = "0000000000000000";

// The kurage:checksum entry as OpenVDB serialises string metadata, with the placeholder: the bytes
// sealChecksum looks for. Files that are not OpenVDB's (checkpoints) carry the same bytes.
std::string checksumField();

// FNV-1a 64 (Fowler, Noll, Vo) over bytes, continuing from `hash`.
uint64_t fnv1a64(std::string_view bytes, uint64_t hash = 0xcbf29ce484222325ull);
// 16 lower-case hex digits.
std::string hex64(uint64_t value);

// Replaces the placeholder of kurage:checksum in the serialised file by its checksum. Throws
// IoError naming `path` if the bytes hold no placeholder (a programming error).
void sealChecksum(std::string& bytes, const std::filesystem::path& path);

// Checks the kurage:checksum of raw file bytes. Throws IoError naming `path` ("not a kurage
// file", "damaged or truncated") on any mismatch.
void verifyChecksum(const std::string& bytes, const std::filesystem::path& path);

// "STAGE HASH FRAME": the stamp as one string, as frames (PNG, EXR) carry it.
std::string stampText(const FileStamp& stamp);

// Compares a parsed file's stamp with what the reader expects; throws IoError naming `path`.
void checkStamp(const FileStamp& found, const FileStamp& expected, const std::filesystem::path& path);

}  // namespace kurage::pipeline

namespace kurage::pipeline {

// Seals the checksum into serialised bytes and writes them atomically (writeFileAtomic).
void writeSealed(const std::filesystem::path& path, std::string bytes);

// Reads a whole file and verifies its checksum; the bytes are then safe to parse.
std::string readVerified(const std::filesystem::path& path);

}  // namespace kurage::pipeline
