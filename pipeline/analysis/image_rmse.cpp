#include "pipeline/analysis/image_rmse.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace kurage::pipeline {

double imageRmse(const render::Image& actual, const render::Image& reference) {
  if (actual.width() != reference.width() || actual.height() != reference.height())
    throw std::invalid_argument("imageRmse: the images differ in size");
  const size_t pixels = size_t(actual.width()) * size_t(actual.height());
  if (pixels == 0) return 0.0;
  double sum = 0.0;
  for (int y = 0; y < actual.height(); ++y)
    for (int x = 0; x < actual.width(); ++x)
      for (int c = 0; c < 3; ++c) {
        const double a = render::linearToSrgb(std::clamp(actual.at(x, y)[c], 0.0f, 1.0f));
        const double b = render::linearToSrgb(std::clamp(reference.at(x, y)[c], 0.0f, 1.0f));
        sum += (a - b) * (a - b);
      }
  return std::sqrt(sum / (3.0 * double(pixels)));
}

}  // namespace kurage::pipeline
