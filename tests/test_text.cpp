// The bitmap font (render/text.h): each glyph stays in its cell, text is 6 font columns a
// character less one wide, a byte outside the font draws the fallback box, and the box and
// outline surround the ink by `scale` pixels.
#include "render/text.h"

#include <gtest/gtest.h>

#include <string>

namespace kurage::render {
namespace {

const Eigen::Vector4f kBlack(0, 0, 0, 1), kWhite(1, 1, 1, 1);

// The bounding box [x0, x1] x [y0, y1] of the pixels that are not black; x0 > x1 when none.
struct Extent {
  int x0 = 1 << 20, y0 = 1 << 20, x1 = -1, y1 = -1;
};
Extent inked(const Image& image) {
  Extent e;
  for (int y = 0; y < image.height(); ++y)
    for (int x = 0; x < image.width(); ++x)
      if (image.at(x, y) != kBlack) {
        e.x0 = std::min(e.x0, x);
        e.y0 = std::min(e.y0, y);
        e.x1 = std::max(e.x1, x);
        e.y1 = std::max(e.y1, y);
      }
  return e;
}

TEST(Text, EveryGlyphDrawsOnlyInsideItsCell) {
  for (int scale : {1, 3})
    for (int code = 32; code <= 126; ++code) {
      SCOPED_TRACE(std::string(1, char(code)) + " at scale " + std::to_string(scale));
      Image image(60, 60, kBlack);
      drawText(image, 7, 5, std::string(1, char(code)), {scale, kWhite, {0, 0, 0, 0}, {0, 0, 0, 0}});
      const Extent e = inked(image);
      if (code == ' ') {
        EXPECT_LT(e.x1, 0);
        continue;
      }
      ASSERT_GE(e.x1, 0);  // something drawn
      EXPECT_GE(e.x0, 7);
      EXPECT_GE(e.y0, 5);
      EXPECT_LT(e.x1, 7 + kGlyphColumns * scale);
      EXPECT_LT(e.y1, 5 + kGlyphRows * scale);
    }
}

TEST(Text, WidthIsSixColumnsACharacterLessOne) {
  EXPECT_EQ(textWidth("", 2), 0);
  EXPECT_EQ(textWidth("a", 1), 5);
  EXPECT_EQ(textWidth("t = 4 s", 2), 2 * (6 * 7 - 1));
  EXPECT_EQ(textHeight(3), 27);
  // "M" fills its cell's first and last columns and the capitals' 7 rows: the ink spans the width.
  for (int n : {1, 4}) {
    const std::string text(size_t(n), 'M');
    Image image(80, 40, kBlack);
    drawText(image, 3, 2, text, {2, kWhite, {0, 0, 0, 0}, {0, 0, 0, 0}});
    const Extent e = inked(image);
    EXPECT_EQ(e.x0, 3);
    EXPECT_EQ(e.x1 - e.x0 + 1, textWidth(text, 2)) << n;
    EXPECT_EQ(e.y1 - e.y0 + 1, 7 * 2);
  }
}

TEST(Text, AByteOutsideTheFontDrawsTheFallbackBox) {
  for (const char* text : {"\x01", "\xc3", "\x7f"}) {
    SCOPED_TRACE(int(static_cast<unsigned char>(text[0])));
    Image image(10, 12, kBlack);
    drawText(image, 1, 1, text, {1, kWhite, {0, 0, 0, 0}, {0, 0, 0, 0}});
    for (int row = 0; row < kGlyphRows; ++row)
      for (int column = 0; column < kGlyphColumns; ++column) {
        const bool border = row < 7 && (row == 0 || row == 6 || column == 0 || column == 4);
        EXPECT_EQ(image.at(1 + column, 1 + row), border ? kWhite : kBlack) << column << ", " << row;
      }
  }
}

TEST(Text, BoxAndOutlineSurroundTheInkByTheScale) {
  const Eigen::Vector4f grey(0.5f, 0.5f, 0.5f, 1), red(1, 0, 0, 1);
  Image image(30, 30, grey);
  // "." is the 2 x 2 square at columns 1-2, rows 5-6; at scale 2 its ink is x 12-15, y 20-23.
  drawText(image, 10, 10, ".", {2, kWhite, red, {0, 0, 0, 0.5f}});
  EXPECT_EQ(image.at(12, 20), kWhite);
  EXPECT_EQ(image.at(15, 23), kWhite);
  EXPECT_EQ(image.at(11, 20), red);  // the outline: 2 px around the ink
  EXPECT_EQ(image.at(10, 18), red);
  EXPECT_EQ(image.at(17, 25), red);
  EXPECT_EQ(image.at(18, 20), Eigen::Vector4f(0.25f, 0.25f, 0.25f, 1));  // the box only: half black
  EXPECT_EQ(image.at(8, 8), Eigen::Vector4f(0.25f, 0.25f, 0.25f, 1));    // its corner, 2 px out
  EXPECT_EQ(image.at(7, 8), grey);                                       // outside the box
  EXPECT_EQ(image.at(10 + textWidth(".", 2) + 2, 10), grey);
  // Text reaching past the image's edges is clipped, not an error.
  drawText(image, -5, 25, "WW", {2, kWhite, red, {0, 0, 0, 0.5f}});
  EXPECT_EQ(image.at(3, 25), kWhite);  // the first W's last column, its top row
}

}  // namespace
}  // namespace kurage::render
