// SPDX-License-Identifier: MIT
/// @file label.hpp
/// Text burnt into a rendered image (tumble render's time label and legend): a 5×7 bitmap font of
/// the digits, `. = - + ( ) / _ % :` and the letters, lower and upper case, white with a dark
/// shadow.
#pragma once
#include <string>
#include <utility>

#include "tumble/viewer/controls.hpp"
#include "tumble/viewer/renderer.hpp"

namespace tumble::viewer {

/// A rectangle of pixels: top-left corner (x, y), y down, `w` × `h` pixels.
struct PixelBox {
  int x = 0, y = 0, w = 0, h = 0;
  bool overlaps(const PixelBox& o) const { return x < o.x + o.w && o.x < x + w && y < o.y + o.h && o.y < y + h; }
};

/// The box drawLabel covers for `text` at (x, y): 6 × `scale` pixels per character (five font
/// pixels and the shadow's one) by 8 × `scale` (seven rows and the shadow's one).
PixelBox labelBox(int x, int y, const std::string& text, int scale);

/// Draws `text` with its top-left corner at (x, y) (pixels, y down), each font pixel `scale`
/// pixels wide; characters the font lacks are drawn as blanks. Clipped to the image. Returns
/// labelBox().
PixelBox drawLabel(Image& img, int x, int y, const std::string& text, int scale);

/// Where drawLegend puts its parts: the ramp and the three texts, none overlapping another.
struct LegendLayout {
  PixelBox bar;          ///< the ramp, without its one-pixel frame
  PixelBox lo, hi, name; ///< the smallest value (under the ramp's left end), the largest (right end), the name
};

/// The legend's layout in a `width` × `height` image, bottom right: the ramp is at least 60 font
/// pixels wide and as wide as the name and as both values side by side with two characters
/// between them; where the image is too narrow for the values side by side, the largest goes on
/// a line of its own under the smallest.
LegendLayout legendLayout(int width, int height, const std::string& lo, const std::string& hi, const std::string& name,
                          int scale);

/// The legend's numbers: `lo` and `hi` in 3 significant digits, more (up to 6) where 3 would
/// print them alike.
std::pair<std::string, std::string> legendValues(float lo, float hi);

/// The colour legend of a ramp colouring (mass, elasticity, speed, height), bottom right: the
/// ramp (rampColor) from `lo` to `hi`, their values under its ends and `name` ("mass kg",
/// "elasticity", a colour file's header) under them, laid out by legendLayout.
LegendLayout drawLegend(Image& img, ColorMode mode, float lo, float hi, const std::string& name, int scale);

/// The label scale for an image `height` pixels high: a glyph about 1/34 of it (1 from 240 up).
int labelScale(int height);

}  // namespace tumble::viewer
