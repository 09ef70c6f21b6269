// runtime/bitmap_font.hpp — a 5x7 pixel font for the words and numbers of a picture's legend.
//
// Why our own: OpenImageIO's render_text needs FreeType, a font file found at run time and the
// image module loaded (which costs most of a small picture's write time); a legend needs only
// digits, signs and a few lowercase words, drawn crisp at whole-pixel scales.
#pragma once

#include <array>
#include <cstdint>
#include <string_view>

namespace fortu {

/// Glyph cell: 5 columns x 7 rows of ink, advanced by 6 columns (one of space).
inline constexpr int kGlyphWidth = 5, kGlyphHeight = 7, kGlyphAdvance = 6;

/// The rows of `c`'s glyph, top first; bit 4 is the leftmost column. Digits, lowercase letters,
/// space and + - . , : = [ ] ( ) / have glyphs; any other character draws as '?'.
std::array<std::uint8_t, kGlyphHeight> glyph_rows(char c);

/// Width in pixels of `text` drawn at `scale` (no trailing space).
constexpr int text_width(std::string_view text, int scale) {
    return text.empty() ? 0 : (static_cast<int>(text.size()) * kGlyphAdvance - 1) * scale;
}

/// Calls `ink(x, y)` for every inked pixel of `text` with its top-left corner at (x0, y0),
/// each font pixel a scale x scale block.
template <typename Ink>
void draw_text(std::string_view text, int x0, int y0, int scale, Ink&& ink) {
    for (std::size_t i = 0; i < text.size(); ++i) {
        const auto rows = glyph_rows(text[i]);
        const int left = x0 + static_cast<int>(i) * kGlyphAdvance * scale;
        for (int r = 0; r < kGlyphHeight; ++r)
            for (int c = 0; c < kGlyphWidth; ++c)
                if (rows[r] >> (kGlyphWidth - 1 - c) & 1)
                    for (int dy = 0; dy < scale; ++dy)
                        for (int dx = 0; dx < scale; ++dx) ink(left + c * scale + dx, y0 + r * scale + dy);
    }
}

}  // namespace fortu
