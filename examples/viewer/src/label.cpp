// SPDX-License-Identifier: MIT
#include "tumble/viewer/label.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>

#include "tumble/viewer/draw_data.hpp"

namespace tumble::viewer {
namespace {

struct Glyph {
  char c;
  std::uint8_t rows[7];  // 5 bits each, the leftmost pixel in bit 4
};

constexpr Glyph kFont[] = {
    {'0', {0x0e, 0x11, 0x13, 0x15, 0x19, 0x11, 0x0e}}, {'1', {0x04, 0x0c, 0x04, 0x04, 0x04, 0x04, 0x0e}},
    {'2', {0x0e, 0x11, 0x01, 0x02, 0x04, 0x08, 0x1f}}, {'3', {0x1f, 0x02, 0x04, 0x02, 0x01, 0x11, 0x0e}},
    {'4', {0x02, 0x06, 0x0a, 0x12, 0x1f, 0x02, 0x02}}, {'5', {0x1f, 0x10, 0x1e, 0x01, 0x01, 0x11, 0x0e}},
    {'6', {0x06, 0x08, 0x10, 0x1e, 0x11, 0x11, 0x0e}}, {'7', {0x1f, 0x01, 0x02, 0x04, 0x08, 0x08, 0x08}},
    {'8', {0x0e, 0x11, 0x11, 0x0e, 0x11, 0x11, 0x0e}}, {'9', {0x0e, 0x11, 0x11, 0x0f, 0x01, 0x02, 0x0c}},
    {'.', {0x00, 0x00, 0x00, 0x00, 0x00, 0x0c, 0x0c}}, {'=', {0x00, 0x00, 0x1f, 0x00, 0x1f, 0x00, 0x00}},
    {'-', {0x00, 0x00, 0x00, 0x1f, 0x00, 0x00, 0x00}}, {'x', {0x00, 0x00, 0x11, 0x0a, 0x04, 0x0a, 0x11}},
    {'(', {0x02, 0x04, 0x08, 0x08, 0x08, 0x04, 0x02}}, {')', {0x08, 0x04, 0x02, 0x02, 0x02, 0x04, 0x08}},
    {'/', {0x01, 0x01, 0x02, 0x04, 0x08, 0x10, 0x10}}, {'+', {0x00, 0x04, 0x04, 0x1f, 0x04, 0x04, 0x00}}, {'a', {0x00, 0x00, 0x0e, 0x01, 0x0f, 0x11, 0x0f}},
    {'b', {0x10, 0x10, 0x16, 0x19, 0x11, 0x11, 0x1e}}, {'c', {0x00, 0x00, 0x0e, 0x10, 0x10, 0x11, 0x0e}},
    {'d', {0x01, 0x01, 0x0d, 0x13, 0x11, 0x11, 0x0f}}, {'e', {0x00, 0x00, 0x0e, 0x11, 0x1f, 0x10, 0x0e}},
    {'f', {0x06, 0x09, 0x08, 0x1c, 0x08, 0x08, 0x08}}, {'g', {0x00, 0x00, 0x0f, 0x11, 0x0f, 0x01, 0x0e}},
    {'h', {0x10, 0x10, 0x16, 0x19, 0x11, 0x11, 0x11}}, {'i', {0x04, 0x00, 0x0c, 0x04, 0x04, 0x04, 0x0e}},
    {'j', {0x02, 0x00, 0x06, 0x02, 0x02, 0x12, 0x0c}}, {'k', {0x10, 0x10, 0x12, 0x14, 0x18, 0x14, 0x12}},
    {'l', {0x0c, 0x04, 0x04, 0x04, 0x04, 0x04, 0x0e}}, {'m', {0x00, 0x00, 0x1a, 0x15, 0x15, 0x11, 0x11}},
    {'n', {0x00, 0x00, 0x16, 0x19, 0x11, 0x11, 0x11}}, {'o', {0x00, 0x00, 0x0e, 0x11, 0x11, 0x11, 0x0e}},
    {'p', {0x00, 0x00, 0x1e, 0x11, 0x1e, 0x10, 0x10}}, {'q', {0x00, 0x00, 0x0d, 0x13, 0x0f, 0x01, 0x01}},
    {'r', {0x00, 0x00, 0x16, 0x19, 0x10, 0x10, 0x10}}, {'s', {0x00, 0x00, 0x0e, 0x10, 0x0e, 0x01, 0x1e}},
    {'t', {0x08, 0x08, 0x1c, 0x08, 0x08, 0x09, 0x06}}, {'u', {0x00, 0x00, 0x11, 0x11, 0x11, 0x13, 0x0d}},
    {'v', {0x00, 0x00, 0x11, 0x11, 0x11, 0x0a, 0x04}}, {'w', {0x00, 0x00, 0x11, 0x11, 0x15, 0x15, 0x0a}},
    {'y', {0x00, 0x00, 0x11, 0x11, 0x0f, 0x01, 0x0e}}, {'z', {0x00, 0x00, 0x1f, 0x02, 0x04, 0x08, 0x1f}},
};

const Glyph* glyphOf(char c) {
  for (const Glyph& g : kFont)
    if (g.c == c) return &g;
  return nullptr;
}

void fill(Image& img, int x0, int y0, int size, std::uint8_t v) {
  for (int y = std::max(0, y0); y < std::min(img.height, y0 + size); ++y)
    for (int x = std::max(0, x0); x < std::min(img.width, x0 + size); ++x) {
      std::uint8_t* p = &img.rgb[3 * (static_cast<std::size_t>(y) * static_cast<std::size_t>(img.width) +
                                      static_cast<std::size_t>(x))];
      p[0] = p[1] = p[2] = v;
    }
}

}  // namespace

PixelBox labelBox(int x, int y, const std::string& text, int scale) {
  scale = std::max(1, scale);
  return {x, y, 6 * scale * static_cast<int>(text.size()), 8 * scale};
}

PixelBox drawLabel(Image& img, int x, int y, const std::string& text, int scale) {
  scale = std::max(1, scale);
  for (int pass = 0; pass < 2; ++pass) {  // the shadow one font pixel down and right, then the text
    const int off = pass == 0 ? scale : 0;
    const std::uint8_t v = pass == 0 ? 20 : 255;
    int cx = x;
    for (const char c : text) {
      if (const Glyph* g = glyphOf(c)) {
        for (int r = 0; r < 7; ++r)
          for (int col = 0; col < 5; ++col)
            if (g->rows[r] & (0x10 >> col)) fill(img, cx + col * scale + off, y + r * scale + off, scale, v);
      }
      cx += 6 * scale;
    }
  }
  return labelBox(x, y, text, scale);
}

LegendLayout legendLayout(int width, int height, const std::string& lo, const std::string& hi, const std::string& name,
                          int scale) {
  scale = std::max(1, scale);
  const int margin = 4 * scale, barH = 5 * scale, gap = 12 * scale, pitch = 9 * scale;
  const int wLo = labelBox(0, 0, lo, scale).w, wHi = labelBox(0, 0, hi, scale).w,
            wName = labelBox(0, 0, name, scale).w;
  const int room = width - 2 * margin;
  const bool sideBySide = wLo + gap + wHi <= room;
  const int barW = std::max({60 * scale, sideBySide ? wLo + gap + wHi : std::max(wLo, wHi), wName});
  const int lines = sideBySide ? 2 : 3;
  LegendLayout l;
  // Bottom right (clear of the time label at the top left at any size): the ramp, 2 font pixels,
  // then the lines of text 9 font pixels apart.
  l.bar = {width - margin - barW, height - margin - (barH + 2 * scale + lines * pitch - scale), barW, barH};
  const int ty = l.bar.y + barH + 2 * scale;
  l.lo = labelBox(l.bar.x, ty, lo, scale);
  l.hi = labelBox(l.bar.x + barW - wHi, sideBySide ? ty : ty + pitch, hi, scale);
  l.name = labelBox(l.bar.x, ty + (lines - 1) * pitch, name, scale);
  return l;
}

std::pair<std::string, std::string> legendValues(float lo, float hi) {
  char a[32], b[32];
  for (int digits = 3;; ++digits) {
    std::snprintf(a, sizeof a, "%.*g", digits, static_cast<double>(lo));
    std::snprintf(b, sizeof b, "%.*g", digits, static_cast<double>(hi));
    if (digits == 6 || lo == hi || std::string(a) != b) return {a, b};
  }
}

LegendLayout drawLegend(Image& img, ColorMode mode, float lo, float hi, const std::string& name, int scale) {
  scale = std::max(1, scale);
  const auto [a, b] = legendValues(lo, hi);
  const LegendLayout l = legendLayout(img.width, img.height, a, b, name, scale);
  const int x0 = l.bar.x, y0 = l.bar.y, barW = l.bar.w, barH = l.bar.h;
  for (int y = std::max(0, y0 - 1); y < std::min(img.height, y0 + barH + 1); ++y)
    for (int x = std::max(0, x0 - 1); x < std::min(img.width, x0 + barW + 1); ++x) {
      std::uint8_t* p = &img.rgb[3 * (static_cast<std::size_t>(y) * static_cast<std::size_t>(img.width) +
                                      static_cast<std::size_t>(x))];
      const bool edge = y < y0 || y >= y0 + barH || x < x0 || x >= x0 + barW;
      const Rgb c = edge ? Rgb{0.1f, 0.1f, 0.1f} : rampColor(mode, float(x - x0) / float(std::max(1, barW - 1)));
      p[0] = static_cast<std::uint8_t>(std::lround(255.0f * std::clamp(c.r, 0.0f, 1.0f)));
      p[1] = static_cast<std::uint8_t>(std::lround(255.0f * std::clamp(c.g, 0.0f, 1.0f)));
      p[2] = static_cast<std::uint8_t>(std::lround(255.0f * std::clamp(c.b, 0.0f, 1.0f)));
    }
  drawLabel(img, l.lo.x, l.lo.y, a, scale);
  drawLabel(img, l.hi.x, l.hi.y, b, scale);
  drawLabel(img, l.name.x, l.name.y, name, scale);
  return l;
}

int labelScale(int height) { return std::max(1, height / 240); }

}  // namespace tumble::viewer
