// PNG files through libpng: 8-bit RGB with text chunks, written atomically (*.part, rename).
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "core/error.h"
#include "core/image.h"

namespace reel::io {

using TextChunks = std::vector<std::pair<std::string, std::string>>;

// level: zlib compression 0..9. Level 1 is ~10x faster than the default for rendered frames and
// only slightly larger.
Status writePng(const std::string& path, const Image& img, const TextChunks& text = {}, int level = 1);
// Reads an 8-bit or 16-bit PNG of any colour type as RGB8 (alpha dropped, palettes expanded).
Result<Image> readPng(const std::string& path, std::size_t max_pixels = 64u << 20);
// The text chunks of a PNG (for tests and tools).
Result<TextChunks> readPngText(const std::string& path);

}  // namespace reel::io
