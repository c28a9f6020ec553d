// Environment pictures for image-based light (render.environment.file): equirectangular
// radiance maps in linear RGB, core/environment.h's layout.
#pragma once

#include <string>

#include "core/environment.h"
#include "core/error.h"

namespace reel::io {

// Reads .hdr (Radiance RGBE, flat or run-length encoded), .exr (OpenEXR, half or float RGB[A])
// or .png (8-bit sRGB, decoded to linear). Anything else, a truncated or corrupt file, or a
// picture of more than max_pixels is a BadInput error naming the file.
Result<RadianceMap> readEnvironmentMap(const std::string& path, std::size_t max_pixels = 16u << 20);

}  // namespace reel::io
