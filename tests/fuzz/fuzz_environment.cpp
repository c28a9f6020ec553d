// libFuzzer target: an environment picture (the first byte picks .hdr, .exr or .png) through
// io::readEnvironmentMap: the Radiance header and its run-length scanlines, OpenEXR's reader, PNG.
// A refusal (BadInput) is the expected answer; the picture is capped at a million pixels here so
// that a valid large one is quick (the cap's own check is the same code as at 16 million).
#include <ImfRgbaFile.h>

#include <cstddef>
#include <cstdint>
#include <string>

#include "core/image.h"
#include "fuzz_files.h"
#include "io/environment_file.h"
#include "io/png.h"

namespace {

const char* const kNames[] = {"env.hdr", "env.exr", "env.png"};

void writeSeeds() {
  using reel::fuzz::seed;
  // 8 x 2: a run-length scanline, then a flat one; and a flat picture without run-length.
  std::string rle = "#?RADIANCE\n# reel seed\nFORMAT=32-bit_rle_rgbe\nEXPOSURE=1.0\n\n-Y 2 +X 8\n";
  rle += std::string{2, 2, 0, 8};
  for (int v : {128, 64, 32, 129}) rle += std::string{static_cast<char>(128 + 8), static_cast<char>(v)};
  for (int x = 0; x < 8; ++x) rle += std::string(4, static_cast<char>(128));
  seed("rle.hdr", 0, rle);
  std::string flat = "#?RGBE\nFORMAT=32-bit_rle_rgbe\n\n+Y 3 +X 4\n";
  for (int k = 0; k < 12; ++k) flat += std::string{char(100 + k), char(50), char(20), char(128)};
  seed("flat.hdr", 0, flat);
  const std::string exr = reel::fuzz::privateDir() + "/seed.exr";
  {
    Imf::Rgba px[4 * 3];
    for (int k = 0; k < 12; ++k) px[k] = Imf::Rgba(static_cast<float>(k) * 0.5f, 0.25f, 3.0f, 1.0f);
    Imf::RgbaOutputFile out(exr.c_str(), 4, 3, Imf::WRITE_RGBA);
    out.setFrameBuffer(px, 1, 4);
    out.writePixels(3);
  }
  seed("small.exr", 1, reel::fuzz::slurp(exr));
  reel::Image img(4, 3);
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 4; ++x) {
      std::uint8_t* p = img.pixel(x, y);
      p[0] = static_cast<std::uint8_t>(60 * x);
      p[1] = static_cast<std::uint8_t>(80 * y);
      p[2] = 200;
    }
  const std::string png = reel::fuzz::privateDir() + "/seed.png";
  if (!reel::io::writePng(png, img)) std::abort();
  seed("small.png", 2, reel::fuzz::slurp(png));
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  if (reel::fuzz::seedDir()) {
    writeSeeds();
    std::exit(0);
  }
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  const std::string path = reel::fuzz::put(kNames[data[0] % 3], {reinterpret_cast<const char*>(data + 1), size - 1});
  (void)reel::io::readEnvironmentMap(path, std::size_t{1} << 20);
  return 0;
}
