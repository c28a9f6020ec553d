// A frame as the mean of several pictures: motion blur and depth of field.
//
// Motion blur by sub-frame accumulation: a film camera's shutter stays open for a part of each
// frame interval (the shutter angle: 180° is half of it), so what moves is smeared along its
// path. The picture of frame k is the mean of `shutter_samples` pictures of the scene at times
// inside the interval before it, each drawn from the draw lists of frames k − 1 and k with their
// geometry interpolated (Korein & Badler 1983's temporal anti-aliasing by supersampling in time;
// Cook, Porter & Carpenter 1984 spread the samples over the shutter).
#pragma once

#include <vector>

#include "core/drawlist.h"

namespace reel {

// The pictures a frame is the mean of: the shutter's samples with motion blur (and a frame
// before), the lens' with depth of field, the larger of the two with both; else 1.
int picturesPerFrame(const DrawList& list);

// Picture j of n: the shutter's time j (when blurring) and the camera moved to point j of the
// lens, still looking at the point in focus on its axis (an accumulation-buffer depth of field,
// Haeberli & Akeley 1990: the lens points on a Vogel spiral over the aperture's disc, each
// covering an equal area). What lies at the focus distance stays put, nearer and farther things
// spread over the circle of confusion A·|d − f|/d measured on the plane in focus.
DrawList picture(const DrawList& list, int j, int n);

// The sample times as fractions of the frame interval from frame k − 1 (0) to frame k (1):
// the midpoints of `samples` equal parts of the open shutter [1 − shutter/360, 1].
std::vector<double> shutterTimes(double shutter_deg, int samples);

// The draw list at fraction s between `before` (frame k − 1) and `after` (frame k): `after` with
// the geometry that both frames have alike moved back along the straight line between them.
// Alike means the same item (drawn by the same body as its same ordinal, `source`; objects and
// items of no body by their index) with the same count: a per-frame mesh of as many
// vertices and indices (positions interpolated, normals interpolated and renormalised), spheres,
// tubes and instanced copies of as many (centres, ends and transforms interpolated, wave phases
// along the shorter way round); the camera's position, target and field of view. Anything else
// (a liquid surface remeshed, particles emitted, a sheet torn) is drawn as it is at frame k.
// The result's `previous` is null.
DrawList shutterSample(const DrawList& before, const DrawList& after, double s);

}  // namespace reel
