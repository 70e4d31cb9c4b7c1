// libFuzzer target: the scene loader (pipeline/scene.h loadScene) on arbitrary bytes. Contract:
// a Scene, or a SceneError naming the file; never a crash, a hang, another exception or an
// allocation beyond the loader's own limits (run with -rss_limit_mb, tests/fuzz/README.md).
#include "pipeline/scene.h"
#include "tests/fuzz/fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const std::filesystem::path file = kurage::fuzz::scratch() / "scene.json";
  kurage::fuzz::writeInput(file, data, size);
  try {
    (void)kurage::pipeline::loadScene(file);
  } catch (const kurage::pipeline::SceneError& e) {
    kurage::fuzz::requireNamesFile(e, file);
  }
  return 0;
}
