// Output files are never half-written: everything is written to a temporary name beside the
// target and renamed into place (rename is atomic within a file system).
#pragma once

#include <filesystem>
#include <string>

namespace kurage::pipeline {

// The temporary name used for `target` while it is being written.
std::filesystem::path temporaryPathFor(const std::filesystem::path& target);

// Writes text to `target` atomically. Throws std::runtime_error naming the path.
void writeTextAtomic(const std::filesystem::path& target, const std::string& text);

// Reads a whole file. Throws std::runtime_error naming the path.
std::string readText(const std::filesystem::path& path);

// "OUT/particles/0042.vdb" style names.
std::filesystem::path frameFile(const std::filesystem::path& folder, int frame, const char* extension);

}  // namespace kurage::pipeline
