// Textures reel draws itself (no downloaded art): chosen in a scene with a material's `pattern`.
#pragma once

#include <string_view>

#include "core/image.h"
#include "core/types.h"

namespace reel {

// An ornamental rug: fringe, a navy border with gold diamonds, a running-zigzag band, a red
// field with a lattice, a central medallion and quarter medallions in the corners. Square,
// `size` pixels a side, sRGB.
Image makeRugTexture(int size);

// A sandy seabed: pale warm sand, soft wind- or wave-made ripple bands, fine grain and a few
// darker and lighter grains. Tileable (the right edge continues into the left, the bottom into
// the top), square, `size` pixels a side, sRGB; the same pixels on every machine.
Image makeSandTexture(int size);

// Floorboards (a wooden floor or table top): 20 planks across the tile running along its x, each
// board its own tint, grain and end joints; tileable, sRGB, the same pixels on every machine.
Image makeWoodTexture(int size);
// Smooth studio concrete: soft grey patches, fine grain, a few pores; tileable, sRGB.
Image makeConcreteTexture(int size);

// A fish's skin, unrolled: u (x) runs nose to tail, v (y) around the body from the back (top
// row) over the left flank to the belly (middle row) and back up the right flank. `base` and
// `mark` are linear colours; the pattern (stripes, spots, gradient or plain) is drawn in `mark` on
// `base`, with the back darker and the belly pale (countershading). sRGB pixels.
Image makeFishSkin(std::string_view pattern, const Vec3& base, const Vec3& mark, int width);

// The pattern of that name at `size` pixels, or an empty image for an unknown name.
Image makePattern(std::string_view name, int size);
inline constexpr std::string_view kPatternNames[] = {"rug", "sand", "wood", "concrete"};

}  // namespace reel
