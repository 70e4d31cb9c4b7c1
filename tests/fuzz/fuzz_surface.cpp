// libFuzzer target: the surface-file reader (pipeline/io/surface_file.h readSurfaceFile).
// Contract: level sets, or an IoError naming the file; never a crash inside OpenVDB's reader
// (the checksum stops damaged bytes before it, pipeline/io/stamp.h).
#include "pipeline/io/surface_file.h"
#include "tests/fuzz/fuzz_util.h"

#include <stdexcept>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const std::filesystem::path file = kurage::fuzz::scratch() / "0000.vdb";
  kurage::fuzz::writeInput(file, data, size);
  try {
    (void)kurage::pipeline::readSurfaceFile(file);
  } catch (const std::runtime_error& e) {
    kurage::fuzz::requireNamesFile(e, file);
  }
  return 0;
}
