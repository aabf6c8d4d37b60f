#pragma once
/// \file detail/tiny_font.hpp
/// A 3×5 pixel font (digits, capitals, a few signs) for the labels of pictures' legends: enough
/// to say what a colour means without an image library.

#include "../image.hpp"

#include <array>
#include <cctype>
#include <cstdint>
#include <string>

namespace areamatch::detail {

/// The glyph of `c` as five rows of three bits (the leftmost bit highest); blank for characters
/// it does not know. Lower case is drawn as upper case.
inline std::array<std::uint8_t, 5> tiny_glyph(char c) {
  switch (std::toupper(static_cast<unsigned char>(c))) {
    case '0': return {7, 5, 5, 5, 7};
    case '1': return {2, 6, 2, 2, 7};
    case '2': return {7, 1, 7, 4, 7};
    case '3': return {7, 1, 3, 1, 7};
    case '4': return {5, 5, 7, 1, 1};
    case '5': return {7, 4, 7, 1, 7};
    case '6': return {7, 4, 7, 5, 7};
    case '7': return {7, 1, 1, 2, 2};
    case '8': return {7, 5, 7, 5, 7};
    case '9': return {7, 5, 7, 1, 7};
    case 'A': return {2, 5, 7, 5, 5};
    case 'B': return {6, 5, 6, 5, 6};
    case 'C': return {3, 4, 4, 4, 3};
    case 'D': return {6, 5, 5, 5, 6};
    case 'E': return {7, 4, 6, 4, 7};
    case 'F': return {7, 4, 6, 4, 4};
    case 'G': return {3, 4, 5, 5, 3};
    case 'H': return {5, 5, 7, 5, 5};
    case 'I': return {7, 2, 2, 2, 7};
    case 'J': return {1, 1, 1, 5, 2};
    case 'K': return {5, 5, 6, 5, 5};
    case 'L': return {4, 4, 4, 4, 7};
    case 'M': return {5, 7, 7, 5, 5};
    case 'N': return {6, 5, 5, 5, 5};
    case 'O': return {2, 5, 5, 5, 2};
    case 'P': return {6, 5, 6, 4, 4};
    case 'Q': return {2, 5, 5, 6, 3};
    case 'R': return {6, 5, 6, 5, 5};
    case 'S': return {3, 4, 2, 1, 6};
    case 'T': return {7, 2, 2, 2, 2};
    case 'U': return {5, 5, 5, 5, 7};
    case 'V': return {5, 5, 5, 5, 2};
    case 'W': return {5, 5, 7, 7, 5};
    case 'X': return {5, 5, 2, 5, 5};
    case 'Y': return {5, 5, 2, 2, 2};
    case 'Z': return {7, 1, 2, 4, 7};
    case '.': return {0, 0, 0, 0, 2};
    case ',': return {0, 0, 0, 2, 4};
    case ':': return {0, 2, 0, 2, 0};
    case '-': return {0, 0, 7, 0, 0};
    case '+': return {0, 2, 7, 2, 0};
    case '>': return {4, 2, 1, 2, 4};
    case '<': return {1, 2, 4, 2, 1};
    case '(': return {1, 2, 2, 2, 1};
    case ')': return {4, 2, 2, 2, 4};
    case '/': return {1, 1, 2, 4, 4};
    case '%': return {5, 1, 2, 4, 5};
    case '_': return {0, 0, 0, 0, 7};
    case '=': return {0, 7, 0, 7, 0};
    case '#': return {5, 7, 5, 7, 5};
    default: return {0, 0, 0, 0, 0};
  }
}

/// Width in pixels of `text` drawn at `scale` (4·scale a character, the last one's gap kept).
inline int tiny_text_width(const std::string& text, int scale) { return static_cast<int>(text.size()) * 4 * scale; }

/// Draws `text` with its top-left corner at (x, y), each font pixel a `scale` × `scale` square;
/// what falls outside the image is clipped.
inline void draw_tiny_text(RgbImage& image, int x, int y, const std::string& text, int scale, std::uint8_t r, std::uint8_t g,
                           std::uint8_t b) {
  for (std::size_t k = 0; k < text.size(); ++k) {
    const auto glyph = tiny_glyph(text[k]);
    for (int row = 0; row < 5; ++row) {
      for (int col = 0; col < 3; ++col) {
        if (!(glyph[static_cast<std::size_t>(row)] & (4 >> col))) continue;
        for (int dy = 0; dy < scale; ++dy) {
          for (int dx = 0; dx < scale; ++dx) {
            const int px = x + (static_cast<int>(k) * 4 + col) * scale + dx, py = y + row * scale + dy;
            if (px >= 0 && py >= 0 && px < image.width && py < image.height) image.set(px, py, r, g, b);
          }
        }
      }
    }
  }
}

}  // namespace areamatch::detail
