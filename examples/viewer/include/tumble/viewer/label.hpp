// SPDX-License-Identifier: MIT
/// @file label.hpp
/// Text burnt into a rendered image (tumble render's time label): a 5×7 bitmap font of the
/// digits, `. = - + x ( ) /` and the lower-case letters, white with a dark shadow.
#pragma once
#include <string>

#include "tumble/viewer/controls.hpp"
#include "tumble/viewer/renderer.hpp"

namespace tumble::viewer {

/// Draws `text` with its top-left corner at (x, y) (pixels, y down), each font pixel `scale`
/// pixels wide; characters the font lacks are drawn as blanks. Clipped to the image.
void drawLabel(Image& img, int x, int y, const std::string& text, int scale);

/// The colour legend of the mass or elasticity colouring, bottom right: a ramp (rampColor) from
/// `lo` to `hi`, their values and `name` ("mass kg", "elasticity") under it.
void drawLegend(Image& img, ColorMode mode, float lo, float hi, const std::string& name, int scale);

/// The label scale for an image `height` pixels high: a glyph about 1/34 of it (1 from 240 up).
int labelScale(int height);

}  // namespace tumble::viewer
