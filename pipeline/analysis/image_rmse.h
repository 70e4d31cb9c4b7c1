// The difference between two images, as the render studies and benchmarks measure it.
#pragma once

#include "render/image.h"

namespace kurage::pipeline {

// Root mean square difference of the RGB channels in sRGB-encoded values (clamped to [0, 1], as
// PNG stores them), over every pixel. Throws std::invalid_argument when the sizes differ.
double imageRmse(const render::Image& actual, const render::Image& reference);

}  // namespace kurage::pipeline
