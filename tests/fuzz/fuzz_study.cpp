// libFuzzer target: the study loader (pipeline/studies/study.h loadStudy), which also loads and checks
// the base scene and every knob combination. The input is written as scenes/studies/input.json
// in a scratch copy of the source tree's scenes/ and tests/data/, so that the committed studies'
// relative paths resolve. Contract: a Study, or a SceneError naming a file; nothing else.
#include "pipeline/studies/study.h"
#include "tests/fuzz/fuzz_util.h"

namespace fs = std::filesystem;

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  const fs::path root = kurage::fuzz::scratch();
  fs::create_directories(root / "tests");
  fs::copy(fs::path(KURAGE_SOURCE_DIR) / "scenes", root / "scenes", fs::copy_options::recursive);
  fs::copy(fs::path(KURAGE_SOURCE_DIR) / "tests" / "data", root / "tests" / "data", fs::copy_options::recursive);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const fs::path file = kurage::fuzz::scratch() / "scenes" / "studies" / "input.json";
  kurage::fuzz::writeInput(file, data, size);
  try {
    (void)kurage::pipeline::loadStudy(file);
  } catch (const kurage::pipeline::SceneError& e) {
    // The study's own error, or its base scene's, which names that (existing) scene file.
    if (e.file() != file.string() && !fs::is_regular_file(e.file())) {
      std::fprintf(stderr, "fuzz: an error naming neither the study nor an existing scene file: %s\n", e.what());
      std::abort();
    }
  }
  return 0;
}
