// Image-diff tests against committed references (tests/references/NAME.png, each made by a scene
// under tests/scenes/), in the manner of Blender's render tests: a per-pixel threshold on the
// sRGB-encoded channels, an allowed fraction of failing pixels, and a bound on the mean error.
//
// On failure the test writes, under build/test_output/NAME/: new.png, reference.png, diff.png
// (|new - reference| amplified 10x) and report.html showing them side by side, and prints the
// report's path. KURAGE_UPDATE_REFERENCES=1 writes the new image as the reference instead
// (`KURAGE_UPDATE_REFERENCES=1 ctest -L image`).
#pragma once

#include "render/image.h"

#include <filesystem>
#include <string>

namespace kurage::test {

struct ImageTolerance {
  float pixelThreshold = 0.016f;         // Blender's default
  float allowedFailingFraction = 0.01f;  // Blender's default: 1 %
  double maxMeanError = 0.005;           // mean |difference| over pixels and channels, sRGB
};

void expectMatchesReference(const render::Image& actual, const std::string& name, const ImageTolerance& tolerance);

// The folder failure output goes to: build/test_output/NAME.
std::filesystem::path testOutputFolder(const std::string& name);

}  // namespace kurage::test
