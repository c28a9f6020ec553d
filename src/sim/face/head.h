// The face's surface and skull: reel's own procedural head, or a user's mesh with its skull mesh
// or an inset. Everything here is in the head's own frame (origin at its centre, +y up, +z out of
// the face, +x the head's left), in metres.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/image.h"
#include "core/scene/face.h"
#include "core/types.h"

namespace reel {

struct FaceSurface {
  std::vector<Vec3> skin;   // surface vertices
  std::vector<Vec3> bone;   // the skull point under each
  std::vector<Vec3> color;  // linear rgb per vertex (skin, lips, brows, hair)
  std::vector<double> jaw;  // 0..1: how much of the jaw's rotation the bone point takes
  std::vector<std::uint8_t> held;  // 1: the tissue here is held to the skull (reel's head: the neck's cut end)
  std::vector<std::uint32_t> tris;  // three per triangle, counter-clockwise from outside
  // reel's head only (generated = true): eyes, mouth, jaw hinge, the grid for placing muscles.
  bool generated = false;
  std::array<Vec3, 2> eye{Vec3::Zero(), Vec3::Zero()};  // centres, left (+x) then right
  double eye_radius = 0.0;
  Vec3 mouth{0, 0, 0};       // the middle of the lips' parting
  double mouth_width = 0.0;  // corner to corner, m
  Vec3 jaw_hinge{0, 0, 0};   // a point on the jaw's axis (along x)
  double scale = 1.0;        // height / 0.24
  std::size_t lower_lip = 0; // the lower lip's copies of the parting's vertices start here (0: none)
  // reel's head: texture coordinates per vertex (u from the midline to the back, the same on
  // both sides; v from the crown to the neck), the grid's angles and the parting's height (at
  // 0.24 m) that the skin's texture is made from, and its looks.
  std::vector<std::array<float, 2>> uv;
  std::vector<double> theta, phi;
  double parting_y = 0.0;
  FaceLook look;
  // reel's head: what is drawn but not simulated, in the head's frame: the ears (per-vertex
  // colours; they turn with the skull) and the shoulders in a sweater (they turn a third as far).
  std::shared_ptr<const TriMesh> ears, bust;
  std::size_t size() const { return skin.size(); }
};

// reel's head of `height` (chin to crown) at `resolution` (columns around, rows from crown to
// neck), its skull `thickness` below the skin: brow, eye sockets, nose, cheekbones, lips parted by
// a slit the jaw opens, chin, ears, neck.
FaceSurface makeHead(double height, std::array<int, 2> resolution, double thickness, const FaceLook& look = {});

// reel's head's skin as a texture over its uv, kSkinTexels a side (about 0.2 mm apart on the
// face): skin, lips, brows, hair, pores (an empty image for a user's mesh).
inline constexpr int kSkinTexels = 1024;
std::shared_ptr<const Image> skinTexture(const FaceSurface& s);

// The ears and the shoulders of reel's head at scale (height / 0.24), in the head's frame
// (head_parts.cpp).
std::shared_ptr<const TriMesh> makeEars(double scale, const Vec3& skin);
std::shared_ptr<const TriMesh> makeBust(double scale, const FaceLook& look);

// A user's closed mesh over its skull mesh (closest points) or an inset along the normals;
// BadInput naming `path` when the mesh is open or a layer would cross the skull.
Result<FaceSurface> userHead(const TriMesh& mesh, const TriMesh* skull, double inset, const std::string& path);

// The point of the surface's front (z > 0) nearest (x, y) in the x–y plane: its vertex index.
std::size_t frontVertex(const FaceSurface& s, double x, double y);

}  // namespace reel
