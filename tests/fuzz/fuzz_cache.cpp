// libFuzzer target: the particle-cache reader (pipeline/io/particle_cache.h readParticleFrame).
// Contract: a frame, or an error naming the file; never a crash or an allocation driven by a
// damaged header. The checksum (pipeline/io/stamp.h) is checked on the raw bytes before
// OpenVDB's parser sees them, so mutated bytes stop there by design.
#include "pipeline/io/particle_cache.h"
#include "tests/fuzz/fuzz_util.h"

#include <stdexcept>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const std::filesystem::path file = kurage::fuzz::scratch() / "0000.vdb";
  kurage::fuzz::writeInput(file, data, size);
  try {
    const kurage::pipeline::ParticleFrame frame = kurage::pipeline::readParticleFrame(file);
    if (frame.vx.size() != frame.size() || frame.id.size() != frame.size() || frame.kind.size() != frame.size())
      std::abort();  // a frame whose attributes disagree must never come back
  } catch (const std::runtime_error& e) {
    kurage::fuzz::requireNamesFile(e, file);
  }
  return 0;
}
