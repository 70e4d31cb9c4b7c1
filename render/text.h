// Text on images, for the labels of figures: a built-in bitmap font of ASCII 32-126, each glyph
// 5 columns by 9 rows (capitals and digits 7 rows above the baseline, 2 rows of descender below),
// drawn at an integer scale (each font pixel a scale x scale square of image pixels), 1 font
// column between glyphs. So that a label reads on any picture, the ink can sit on a translucent
// box (the text's extent padded by `scale` pixels) and be ringed by an outline `scale` pixels wide.
//
// Colours are linear RGBA, alpha the opacity with which each layer (box, outline, ink) is blended
// over the image, in that order: p = (1 - a) p + a c for RGB, p.a = a + (1 - a) p.a.
// One line of text only (no wrapping; '\n' is no line break). A byte outside 32-126 (so each byte
// of a UTF-8 sequence) draws the fallback glyph, the outline of the 5 x 7 capital cell. Pixels
// outside the image are skipped.
#pragma once

#include "render/image.h"

#include <Eigen/Core>

#include <string_view>

namespace kurage::render {

struct TextStyle {
  int scale = 1;                                               // image pixels per font pixel, >= 1
  Eigen::Vector4f ink = Eigen::Vector4f(1, 1, 1, 1);
  Eigen::Vector4f outline = Eigen::Vector4f(0, 0, 0, 0);       // alpha 0: none
  Eigen::Vector4f box = Eigen::Vector4f(0, 0, 0, 0);           // alpha 0: none
};

inline constexpr int kGlyphColumns = 5, kGlyphRows = 9, kGlyphAdvance = 6;  // font pixels

// The text's extent in image pixels: scale (6 n - 1) wide for n characters (0 when empty), 9
// scale high. The box and outline reach `scale` pixels further on every side.
int textWidth(std::string_view text, int scale);
int textHeight(int scale);

// Draws `text` with the top-left corner of its first glyph's cell at pixel (x, y).
void drawText(Image& image, int x, int y, std::string_view text, const TextStyle& style);

}  // namespace kurage::render
