#include "io/png.h"

#include <png.h>

#include <csetjmp>
#include <cstdio>
#include <cstring>
#include <memory>

#include "io/files.h"

namespace reel::io {
namespace {

struct FileCloser {
  void operator()(std::FILE* f) const {
    if (f) std::fclose(f);
  }
};

}  // namespace

namespace {

// libpng's default handlers print to stderr; reel reports errors itself.
void pngError(png_structp png, png_const_charp) { png_longjmp(png, 1); }
void pngWarning(png_structp, png_const_charp) {}

// The libpng calls, in a frame without C++ objects: libpng reports errors by longjmp.
bool writeRaw(std::FILE* f, const Image& img, png_bytep* rows, png_text* chunks, int nchunks, int level) {
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, pngError, pngWarning);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!png || !info) {
    png_destroy_write_struct(&png, &info);
    return false;
  }
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    return false;
  }
  png_init_io(png, f);
  png_set_compression_level(png, level);
  png_set_filter(png, 0, level <= 1 ? PNG_FILTER_SUB : PNG_ALL_FILTERS);
  png_set_IHDR(png, info, static_cast<png_uint_32>(img.width), static_cast<png_uint_32>(img.height), 8,
               PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  if (nchunks > 0) png_set_text(png, info, chunks, nchunks);
  png_set_rows(png, info, rows);
  png_write_png(png, info, PNG_TRANSFORM_IDENTITY, nullptr);
  png_destroy_write_struct(&png, &info);
  return true;
}

}  // namespace

Status writePng(const std::string& path, const Image& img, const TextChunks& text, int level) {
  AtomicFile file;
  if (Status st = file.open(path); !st) return st;
  std::vector<png_bytep> rows(static_cast<std::size_t>(img.height));
  for (int y = 0; y < img.height; ++y) rows[static_cast<std::size_t>(y)] = const_cast<png_bytep>(img.pixel(0, y));
  std::vector<png_text> chunks(text.size());
  for (std::size_t i = 0; i < text.size(); ++i) {
    chunks[i].compression = PNG_TEXT_COMPRESSION_NONE;
    chunks[i].key = const_cast<char*>(text[i].first.c_str());
    chunks[i].text = const_cast<char*>(text[i].second.c_str());
    chunks[i].text_length = text[i].second.size();
  }
  if (!writeRaw(file.get(), img, rows.data(), chunks.data(), static_cast<int>(chunks.size()), level))
    return Error(ErrorKind::Output, path + ": write failed (disk full?)");
  return file.commit();
}

namespace {

struct Reader {
  png_structp png = nullptr;
  png_infop info = nullptr;
  std::unique_ptr<std::FILE, FileCloser> f;
  ~Reader() { png_destroy_read_struct(&png, &info, nullptr); }
};

Status openReader(const std::string& path, Reader& r) {
  r.f.reset(std::fopen(path.c_str(), "rb"));
  if (!r.f) return Error(ErrorKind::BadInput, path + ": cannot open: " + std::strerror(errno));
  unsigned char sig[8];
  if (std::fread(sig, 1, 8, r.f.get()) != 8 || png_sig_cmp(sig, 0, 8) != 0)
    return Error(ErrorKind::BadInput, path + ": not a PNG file");
  r.png = png_create_read_struct(PNG_LIBPNG_VER_STRING, nullptr, pngError, pngWarning);
  r.info = r.png ? png_create_info_struct(r.png) : nullptr;
  if (!r.png || !r.info) return Error(ErrorKind::Internal, "out of memory for libpng");
  png_init_io(r.png, r.f.get());
  png_set_sig_bytes(r.png, 8);
  return {};
}

}  // namespace

Result<Image> readPng(const std::string& path, std::size_t max_pixels) {
  Reader r;
  if (Status st = openReader(path, r); !st) return st.error();
  Image img;
  std::vector<png_bytep> rows;
  if (setjmp(png_jmpbuf(r.png))) return Error(ErrorKind::BadInput, path + ": corrupt PNG");
  png_read_info(r.png, r.info);
  const png_uint_32 w = png_get_image_width(r.png, r.info), h = png_get_image_height(r.png, r.info);
  if (w == 0 || h == 0 || static_cast<std::size_t>(w) * h > max_pixels)
    return Error(ErrorKind::BadInput, path + ": image of " + std::to_string(w) + "x" + std::to_string(h) +
                                          " pixels is empty or too large");
  // Any PNG to 8-bit RGB.
  png_set_strip_16(r.png);
  png_set_strip_alpha(r.png);
  png_set_packing(r.png);
  png_set_palette_to_rgb(r.png);
  png_set_expand_gray_1_2_4_to_8(r.png);
  png_set_gray_to_rgb(r.png);
  png_read_update_info(r.png, r.info);
  if (png_get_rowbytes(r.png, r.info) != static_cast<std::size_t>(w) * 3)
    return Error(ErrorKind::BadInput, path + ": unsupported PNG layout");
  img = Image(static_cast<int>(w), static_cast<int>(h));
  rows.resize(h);
  for (png_uint_32 y = 0; y < h; ++y) rows[y] = img.pixel(0, static_cast<int>(y));
  png_read_image(r.png, rows.data());
  png_read_end(r.png, nullptr);
  return img;
}

Result<TextChunks> readPngText(const std::string& path) {
  Reader r;
  if (Status st = openReader(path, r); !st) return st.error();
  TextChunks out;
  if (setjmp(png_jmpbuf(r.png))) return Error(ErrorKind::BadInput, path + ": corrupt PNG");
  png_read_info(r.png, r.info);
  png_textp text = nullptr;
  int n = 0;
  png_get_text(r.png, r.info, &text, &n);
  for (int i = 0; i < n; ++i) out.emplace_back(text[i].key, std::string(text[i].text, text[i].text_length));
  return out;
}

}  // namespace reel::io
