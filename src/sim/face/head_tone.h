// The skin's tone from side to side, and the value noise reel's head is painted with (internal to
// the face kind; head_shape.h has the head's frame and units).
#pragma once

#include "core/types.h"

namespace reel::head {

// Value noise on the unit lattice (smooth, 0..1), by a hash of the cell's corners.
double valueNoise(const Vec3& p);

// The skin's tone unevenly over the face, a factor on its albedo (about 1) at the base point p:
// patches a few centimetres across where the capillaries are denser or the skin paler, different
// on the two sides. The skin's texture (skinColor) is shared by the two halves of the head, so it
// is mirrored; this is drawn on the skin's and the ears' vertices.
Vec3 skinTint(const Vec3& p);

}  // namespace reel::head
