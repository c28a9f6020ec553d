// The face's surface and skull: reel's own procedural head, or a user's mesh with its skull mesh
// or an inset. Everything here is in the head's own frame (origin at its centre, +y up, +z out of
// the face, +x the head's left), in metres.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <span>
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
  std::vector<double> gloss;  // reel's head: the skin's sheen per vertex, −1..1 (head::skinGloss; −1 the hair, dulled)
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
  // reel's head: its grid, for drawing it finer (makeSkinDetail): columns around, the rows of
  // rays (rings 1..rays-1 below the crown's vertex), all rows (the neck's rings below the rays',
  // then the bottom's vertex), the parting's row, each ring's polar angle per column (row-major,
  // C a row), and the vertex each vertex's lower-lip copy is (itself where it has none).
  int columns = 0, rays = 0, rows = 0, parting_row = 0;
  std::vector<double> polar;
  std::vector<std::uint32_t> lower_copy;
  FaceLook look;
  // reel's head: what is drawn but not simulated, in the head's frame: the ears (per-vertex
  // colours; they turn with the skull), the teeth (the upper row with the skull, the lower with
  // the jaw) and the shoulders in a sweater (they turn a third as far).
  std::shared_ptr<const TriMesh> ears, bust;
  std::shared_ptr<const TriMesh> hair;  // strands over the painted cap (per-vertex colours), with the skull
  std::array<std::shared_ptr<const TriMesh>, 2> teeth;  // upper (with the skull), lower (with the jaw)
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
// Its relief, a bump map over the same uv (head::skinRelief; heights as stored, 0..255 for 0..1,
// kSkinReliefDepth m from 0 to 1).
std::shared_ptr<const Image> skinRelief(const FaceSurface& s);
inline constexpr double kSkinReliefDepth = 0.0004;
// Its wrinkle lines (head::wrinkleLines) as a wrinkle map over the same uv: 1 on bare skin, down
// to 0 in a line's floor, kWrinkleDepth m deep where a wrinkle shows in full.
std::shared_ptr<const Image> skinWrinkles(const FaceSurface& s);
inline constexpr double kWrinkleDepth = 0.001;

// reel's head drawn finer than it is simulated: each quad of its grid split level x level, each
// fine point the bilinear blend of its quad's four corners plus an offset, the head's own shape
// there less that blend: what the simulated mesh is too coarse to hold (the nose's wings and
// nostrils, the lips' border, the fold under the lower lip) rides on the tissue's motion.
struct SkinDetail {
  struct Point {
    std::array<std::uint32_t, 4> from{};  // the corners (vertices of the simulated skin)
    std::array<double, 4> w{};            // their weights (sum 1)
    Vec3 offset{0, 0, 0};                 // in the head's rest frame, m
    std::array<float, 2> uv{};
    std::array<float, 3> tint{1, 1, 1};  // head::skinTint at its rest point
  };
  std::vector<Point> points;
  std::vector<std::uint32_t> tris;  // counter-clockwise from outside
  // Per vertex of the simulated skin: how far the fine skin around it dips below its rest
  // surface (m, along its normal; 0 where it does not): a surface inset from the simulated skin by
  // more than this stays under the skin drawn.
  std::vector<double> dip;
  // The fine points for the simulated skin now (`now`; `rest` in the head's frame, `posed` the
  // rest carried by the skull as it is posed now, triangles `coarse_tris`): each offset turned by
  // its corners' rotations from rest (a frame of the normal and an edge at each corner) and
  // blended as the corners are. The corners first lose the ripples a grid step or two long that
  // the tissue makes where a muscle bunches it (the mesh buckling between its nodes): `smoothing`
  // passes relax each corner's displacement from `posed` halfway toward its neighbours' mean.
  // `relaxed`, when given, receives the simulated skin's points after those passes.
  void place(std::span<const Vec3> rest, std::span<const Vec3> posed, std::span<const Vec3> now,
             const std::vector<std::uint32_t>& coarse_tris, int smoothing, std::vector<Vec3>& out,
             std::vector<Vec3>* relaxed = nullptr) const;
  // A per-vertex value of the simulated skin at the fine points.
  double blend(const Point& p, std::span<const double> value) const;
};
SkinDetail makeSkinDetail(const FaceSurface& s, int level);

// A mesh's open edges (edges of one triangle only) as each vertex's neighbours along them, in
// increasing order (none for a vertex on no open edge; `vertices` at least the mesh's count)
// (head_detail.cpp).
std::vector<std::vector<std::uint32_t>> openEdgeNeighbours(const std::vector<std::uint32_t>& tris, std::size_t vertices);

// The ears and the shoulders of reel's head at scale (height / 0.24), in the head's frame
// (head_parts.cpp).
std::shared_ptr<const TriMesh> makeEars(double scale, const Vec3& skin);
std::shared_ptr<const TriMesh> makeBust(double scale, const FaceLook& look);
// The triangles of a ribbon whose points were added in pairs (one on each edge) from `base`,
// `segments` long: each pair joined to the next.
void ribbonTriangles(TriMesh& m, std::uint32_t base, int segments);
// The triangles of a grid of points added row by row from `base`, `rows` + 1 rows of `cols` + 1:
// each cell two triangles.
void gridTriangles(TriMesh& m, std::uint32_t base, int rows, int cols);
// A hair as a ribbon of `segments` pieces: its middle at centre(f) (f from 0 at the root to 1 at
// the tip), `width` wide at the root narrowing to 0.3 of it at the tip, across `side`, facing
// `normal`, coloured colour(f); each point scaled by `scale` (the scalp's hair and the brows').
template <class Centre, class Colour>
void addStrand(TriMesh& m, int segments, double width, const Vec3& side, const Vec3& normal, double scale, Centre&& centre,
               Colour&& colour) {
  const auto base = static_cast<std::uint32_t>(m.vertexCount());
  for (int j = 0; j <= segments; ++j) {
    const double f = static_cast<double>(j) / segments;
    const Vec3 p = centre(f), c = colour(f);
    const double w = 0.5 * width * (1.0 - 0.7 * f);
    for (double e : {-1.0, 1.0}) {
      m.addVertex(scale * (p + e * w * side), normal);
      for (int i = 0; i < 3; ++i) m.colors.push_back(static_cast<float>(c[i]));
    }
  }
  ribbonTriangles(m, base, segments);
}
// The triangles of a grid of rings of `segments` points each from `first` (each ring closing round),
// ring j joined to ring j + 1 for j < `rings`: rings + 1 rings, or with `closed` `rings` rings, the
// last joined to the first (a band round a loop); counter-clockwise from outside, or clockwise
// with `flip`.
void ringTriangles(TriMesh& m, std::uint32_t first, int rings, int segments, bool flip, bool closed = false);
// reel's head's hair as strands rooted in the cap its skin paints, in the head's frame
// (head_hair.cpp); empty for a user's mesh.
std::shared_ptr<const TriMesh> makeHair(const FaceSurface& s);
// A row of teeth (per-vertex albedo), the upper or the lower: its labial face `front` (z)
// at the midline, its incisal edge at height `edge`, in the head's frame at rest.
std::shared_ptr<const TriMesh> makeTeeth(double scale, double front, double edge, bool upper);

// A user's closed mesh over its skull mesh (closest points) or an inset along the normals;
// BadInput naming `path` when the mesh is open or a layer would cross the skull.
Result<FaceSurface> userHead(const TriMesh& mesh, const TriMesh* skull, double inset, const std::string& path);

// The point of the surface's front (z > 0) nearest (x, y) in the x–y plane: its vertex index.
std::size_t frontVertex(const FaceSurface& s, double x, double y);

}  // namespace reel
