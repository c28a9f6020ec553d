#include "io/environment_file.h"

#include "core/image.h"

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>

#include <ImfArray.h>
#include <ImfRgbaFile.h>

#include "io/png.h"

namespace reel::io {
namespace {

Error bad(const std::string& path, const std::string& why) { return Error(ErrorKind::BadInput, path + ": " + why); }

// Radiance's RGBE format (Ward 1991, "Real pixels", Graphics Gems II): a text header ending in an
// empty line, a resolution line "-Y H +X W", then scanlines of 4-byte pixels (mantissas and a
// shared exponent), each either flat or, when it starts with 2 2 and the width, run-length
// encoded channel by channel.
// A header line longer than this is not Radiance's (its lines are a few dozen bytes).
constexpr std::size_t kMaxHdrLine = 4096;

// At most the first 60 bytes of a bad line, for a message.
std::string excerpt(const std::string& l) { return l.size() <= 60 ? l : l.substr(0, 60) + "..."; }

Result<RadianceMap> readHdr(const std::string& path, std::size_t max_pixels) {
  // The largest file a picture of max_pixels can be: 4 bytes a pixel, flat, after a header. A
  // larger one is refused before it is read.
  const std::size_t most = 4 * max_pixels + (1u << 20);
  std::error_code ec;
  const auto size = std::filesystem::file_size(path, ec);
  if (!ec && size > most)
    return bad(path, std::to_string(size) + " bytes, more than a picture of at most " + std::to_string(max_pixels) +
                         " pixels can take (" + std::to_string(most) + ")");
  std::ifstream in(path, std::ios::binary);
  if (!in) return bad(path, "cannot be opened");
  std::string bytes;
  bytes.resize(most + 1);
  in.read(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  bytes.resize(static_cast<std::size_t>(in.gcount()));
  if (bytes.size() > most) return bad(path, "more than a picture of at most " + std::to_string(max_pixels) + " pixels can take");
  std::size_t at = 0;
  bool long_line = false;
  auto line = [&](std::string& out) {
    const std::size_t e = bytes.find('\n', at);
    if (e == std::string::npos || e - at > kMaxHdrLine) {
      long_line = e != std::string::npos || bytes.size() - at > kMaxHdrLine;
      return false;
    }
    out = bytes.substr(at, e - at);
    at = e + 1;
    return true;
  };
  auto tooLong = [&] {
    return bad(path, "a header line longer than " + std::to_string(kMaxHdrLine) + " bytes (\"" + excerpt(bytes.substr(at, 60)) +
                         "\"): not a Radiance .hdr header");
  };
  std::string l;
  if (!line(l) || (l.rfind("#?RADIANCE", 0) != 0 && l.rfind("#?RGBE", 0) != 0))
    return long_line ? tooLong() : bad(path, "not a Radiance .hdr file (no #?RADIANCE header)");
  bool rgbe = true;
  while (line(l) && !l.empty())
    if (l.rfind("FORMAT=", 0) == 0) rgbe = l == "FORMAT=32-bit_rle_rgbe";
  if (long_line) return tooLong();
  if (!rgbe) return bad(path, "only the 32-bit_rle_rgbe format is read (not XYZE)");
  int w = 0, h = 0;
  char ys[3] = {}, xs[3] = {};
  if (!line(l)) return long_line ? tooLong() : bad(path, "ends before its resolution line (-Y H +X W)");
  if (std::sscanf(l.c_str(), "%2s %d %2s %d", ys, &h, xs, &w) != 4 || std::strcmp(ys, "-Y") != 0 ||
      std::strcmp(xs, "+X") != 0 || w <= 0 || h <= 0)
    return bad(path, "unsupported resolution line \"" + excerpt(l) + "\" (expected -Y H +X W)");
  if (static_cast<std::size_t>(w) * h > max_pixels)
    return bad(path, std::to_string(w) + "x" + std::to_string(h) + " is more than the " + std::to_string(max_pixels) + " pixels allowed");
  RadianceMap m;
  m.width = w;
  m.height = h;
  m.rgb.resize(static_cast<std::size_t>(3) * w * h);
  std::vector<unsigned char> row(static_cast<std::size_t>(4) * w);
  auto byte = [&](unsigned char& b) {
    if (at >= bytes.size()) return false;
    b = static_cast<unsigned char>(bytes[at++]);
    return true;
  };
  const std::string truncated = "ends before its last scanline (truncated)";
  for (int y = 0; y < h; ++y) {
    unsigned char head[4];
    for (unsigned char& b : head)
      if (!byte(b)) return bad(path, truncated);
    if (head[0] == 2 && head[1] == 2 && (head[2] << 8 | head[3]) == w && w >= 8 && w < 32768) {
      for (int c = 0; c < 4; ++c)
        for (int x = 0; x < w;) {
          unsigned char n, v;
          if (!byte(n)) return bad(path, truncated);
          if (n > 128) {  // a run of n − 128 copies
            const int run = n - 128;
            if (run > w - x || !byte(v)) return bad(path, "has a corrupt run-length scanline " + std::to_string(y));
            for (int k = 0; k < run; ++k) row[static_cast<std::size_t>(4 * x++ + c)] = v;
          } else {  // n literal bytes
            if (n == 0 || n > w - x) return bad(path, "has a corrupt run-length scanline " + std::to_string(y));
            for (int k = 0; k < n; ++k) {
              if (!byte(v)) return bad(path, truncated);
              row[static_cast<std::size_t>(4 * x++ + c)] = v;
            }
          }
        }
    } else {  // a flat scanline; its first pixel is already read
      std::memcpy(row.data(), head, 4);
      for (std::size_t k = 4; k < row.size(); ++k)
        if (!byte(row[k])) return bad(path, truncated);
    }
    for (int x = 0; x < w; ++x) {
      const unsigned char* p = &row[static_cast<std::size_t>(4 * x)];
      const float f = p[3] ? std::ldexp(1.0f, p[3] - 136) : 0.0f;  // 2^(e − 128) / 256
      for (int c = 0; c < 3; ++c) m.rgb[3 * (static_cast<std::size_t>(y) * w + x) + c] = (p[c] + 0.5f) * f;
    }
  }
  return m;
}

Result<RadianceMap> readExr(const std::string& path, std::size_t max_pixels) {
  try {
    Imf::RgbaInputFile file(path.c_str());
    const Imath::Box2i dw = file.dataWindow();
    const long w = dw.max.x - dw.min.x + 1, h = dw.max.y - dw.min.y + 1;
    if (w <= 0 || h <= 0) return bad(path, "has an empty data window");
    if (static_cast<std::size_t>(w) * static_cast<std::size_t>(h) > max_pixels)
      return bad(path, std::to_string(w) + "x" + std::to_string(h) + " is more than the " + std::to_string(max_pixels) + " pixels allowed");
    Imf::Array2D<Imf::Rgba> px(h, w);
    file.setFrameBuffer(&px[0][0] - dw.min.x - dw.min.y * w, 1, static_cast<std::size_t>(w));
    file.readPixels(dw.min.y, dw.max.y);
    RadianceMap m;
    m.width = static_cast<int>(w);
    m.height = static_cast<int>(h);
    m.rgb.resize(static_cast<std::size_t>(3 * w * h));
    for (long y = 0; y < h; ++y)
      for (long x = 0; x < w; ++x) {
        const Imf::Rgba& p = px[y][x];
        float* o = &m.rgb[static_cast<std::size_t>(3 * (y * w + x))];
        o[0] = p.r, o[1] = p.g, o[2] = p.b;
        for (int c = 0; c < 3; ++c)
          if (!std::isfinite(o[c]) || o[c] < 0) o[c] = 0;  // no negative or infinite light
      }
    return m;
  } catch (const std::exception& e) {
    return bad(path, std::string("OpenEXR cannot read it: ") + e.what());
  }
}

Result<RadianceMap> readPngMap(const std::string& path, std::size_t max_pixels) {
  auto img = readPng(path, max_pixels);
  if (!img.ok()) return img.error();
  RadianceMap m;
  m.width = img.value().width;
  m.height = img.value().height;
  m.rgb.resize(img.value().rgb.size());
  for (std::size_t k = 0; k < m.rgb.size(); ++k) m.rgb[k] = static_cast<float>(srgbToLinear(img.value().rgb[k] / 255.0));
  return m;
}

}  // namespace

Result<RadianceMap> readEnvironmentMap(const std::string& path, std::size_t max_pixels) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (ext == ".hdr") return readHdr(path, max_pixels);
  if (ext == ".exr") return readExr(path, max_pixels);
  if (ext == ".png") return readPngMap(path, max_pixels);
  return bad(path, "an environment must be .hdr, .exr or .png");
}

}  // namespace reel::io
