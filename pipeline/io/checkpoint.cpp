#include "pipeline/io/checkpoint.h"

#include "pipeline/io/files.h"
#include "pipeline/io/stamp.h"

#include <nlohmann/json.hpp>

#include <cstdint>

namespace kurage::pipeline {

namespace fs = std::filesystem;

namespace {
constexpr std::string_view kMagic = "KURAGE-CHECKPOINT 1\n";
}  // namespace

fs::path checkpointFile(const fs::path& outDir) { return outDir / "checkpoint.bin"; }

void writeCheckpoint(const fs::path& path, const Checkpoint& c, const std::string& simHash) {
  const std::string header = nlohmann::json{{"stage", "checkpoint"},
                                            {"scene_hash", simHash},
                                            {"frame", c.frame},
                                            {"time", c.time},
                                            {"kurage", KURAGE_VERSION},
                                            {"sim_state_bytes", c.simState.size()},
                                            {"stage_state_bytes", c.stageState.size()}}
                                 .dump();
  std::string bytes(kMagic);
  bytes += checksumField();
  const uint32_t length = uint32_t(header.size());
  for (int b = 0; b < 4; ++b) bytes.push_back(char((length >> (8 * b)) & 0xff));
  bytes += header;
  bytes += c.simState;
  bytes += c.stageState;
  writeSealed(path, std::move(bytes));
}

Checkpoint readCheckpoint(const fs::path& path, const std::string& simHash) {
  const std::string bytes = readFile(path);
  const auto fail = [&path](const std::string& why) { return IoError(path.string() + ": " + why); };
  if (bytes.compare(0, kMagic.size(), kMagic) != 0) throw fail("not a kurage checkpoint");
  verifyChecksum(bytes, path);
  size_t at = kMagic.size() + checksumField().size();
  if (bytes.size() < at + 4) throw fail("truncated checkpoint header");
  uint32_t length = 0;
  for (int b = 0; b < 4; ++b) length |= uint32_t(static_cast<unsigned char>(bytes[at + size_t(b)])) << (8 * b);
  at += 4;
  if (length > bytes.size() - at) throw fail("truncated checkpoint header");
  nlohmann::json header;
  Checkpoint c;
  size_t simBytes = 0, stageBytes = 0;
  std::string stage, hash, version;
  try {
    header = nlohmann::json::parse(bytes.substr(at, length));
    stage = header.at("stage").get<std::string>();
    hash = header.at("scene_hash").get<std::string>();
    version = header.at("kurage").get<std::string>();
    c.frame = header.at("frame").get<int>();
    c.time = header.at("time").get<double>();
    simBytes = header.at("sim_state_bytes").get<size_t>();
    stageBytes = header.at("stage_state_bytes").get<size_t>();
  } catch (const nlohmann::json::exception& e) {
    throw fail(std::string("unreadable checkpoint header: ") + e.what());
  }
  at += length;
  checkStamp({stage, hash, -1}, {"checkpoint", simHash, -1}, path);
  if (version != KURAGE_VERSION)
    throw fail("made by kurage " + version + ", this is " + KURAGE_VERSION + "; it cannot be resumed");
  if (simBytes > bytes.size() - at || stageBytes != bytes.size() - at - simBytes)
    throw fail("the checkpoint's sections do not add up to its size");
  c.simState = bytes.substr(at, simBytes);
  c.stageState = bytes.substr(at + simBytes);
  return c;
}

}  // namespace kurage::pipeline
