// Indexed triangle meshes and generators of the primitive shapes (sphere, box, capsule, plane),
// shared by sim (what objects look like) and render (instanced prototypes).
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <utility>
#include <vector>

#include "core/types.h"

namespace reel {

struct TriMesh {
  std::vector<float> positions;  // xyz per vertex, m
  std::vector<float> normals;    // xyz per vertex, unit
  std::vector<float> uvs;        // uv per vertex (may be empty)
  std::vector<float> colors;     // linear rgb per vertex, multiplied into the albedo (may be empty)
  std::vector<float> gloss;      // per vertex −1..1: a wet sheen added to the material's highlight; below 0, dulled (hair) (may be empty)
  // per vertex 0..1: the share of the material's transmission that passes here (a liquid's clear
  // and opaque species in one surface); empty: all of it
  std::vector<float> clarity;
  // per vertex 0..1: how deep the material's wrinkle map sinks here (creases that come and go with
  // an expression); empty: not at all
  std::vector<float> wrinkle;
  std::vector<std::uint32_t> indices;  // three per triangle, counter-clockwise seen from outside
  std::size_t vertexCount() const { return positions.size() / 3; }
  std::size_t triangleCount() const { return indices.size() / 3; }
  Vec3 position(std::size_t v) const { return Vec3(positions[3 * v], positions[3 * v + 1], positions[3 * v + 2]); }
  Vec3 normal(std::size_t v) const { return Vec3(normals[3 * v], normals[3 * v + 1], normals[3 * v + 2]); }
  void addVertex(const Vec3& p, const Vec3& n, double u = 0, double v = 0);
  // Applies x ↦ R·x + t to positions and R to normals.
  void transform(const Mat3& R, const Vec3& t);
};

// An imported mesh placed in the world: x ↦ R·(scale ⊙ x) + position; normals take the inverse
// scale and R, renormalised, so they stay perpendicular to the surface.
TriMesh placeMesh(const TriMesh& m, const Vec3& scale, const Mat3& R, const Vec3& position);

// Each point's normal: the sum of its triangles' area vectors (twice their areas along their
// normals; not unit, zero where no triangle touches the point), over `points` with `tris`.
std::vector<Vec3> areaNormals(std::span<const Vec3> points, const std::vector<std::uint32_t>& tris);

// Each point's normal weighted by its triangles' angles there (Thürmer & Wüthrich 1998): unlike the
// area-weighted sum, unchanged when a flat patch of the fan is split differently, so nearly the
// same for any fine triangulation of a smooth surface (unit; +y where no triangle touches the point).
std::vector<Vec3> angleNormals(std::span<const Vec3> points, const std::vector<std::uint32_t>& tris);

// A surface through points[first + k] (k < n) with the triangles `tris` (indices from `first`),
// its normals weighted by angle (angleNormals: a face's skin, a jelly's; area weights bent the
// normals along a face's midline, where its mirrored diagonals meet, and drew a seam down the chin).
std::shared_ptr<TriMesh> smoothMesh(std::span<const Vec3> points, std::size_t first, std::size_t n,
                                    const std::vector<std::uint32_t>& tris);

TriMesh makeUvSphere(double radius, int slices, int stacks);
// An icosahedron whose faces are split in four `subdivisions` times, vertices pushed onto the
// sphere: 20·4^s triangles spread evenly (a UV sphere spends its triangles at the poles), so a
// small one is rounder for its count (80 triangles at s = 1: a silhouette of about 10 sides).
TriMesh makeIcosphere(double radius, int subdivisions);
TriMesh makeBox(const Vec3& size);                 // centred, full extents
TriMesh makeCapsule(const Vec3& a, const Vec3& b, double radius, int slices, int stacks);
// Centred in the x–z plane, normal +y. Its UVs span it once (0..1), or with `tile` > 0 run in
// metres / tile from its −x, −z corner, so that a texture repeats every `tile` metres.
TriMesh makeQuad(double width, double depth, double tile = 0);
// The five boxes of an open container of outer `size` and wall (and floor) thickness `wall`: the
// floor, then the walls at +x, −x, +z, −z, each as (centre relative to the container's centre,
// full size). Shared by the collider and the drawn mesh.
std::array<std::pair<Vec3, Vec3>, 5> containerBoxes(const Vec3& size, double wall);

// Points of a hexagonal lattice `spacing` apart inside a disc of `radius` (the centre always),
// in the disc's own (u, v) coordinates, m. A liquid nozzle's cross-section.
std::vector<std::array<double, 2>> hexDisc(double radius, double spacing);

// A closed cylinder along y, centred: smooth sides and flat caps.
TriMesh makeCylinder(double radius, double height, int slices);
// A unit cylinder along +z from z = 0 to 1, radius 1, open ends (instanced tubes).
TriMesh makeTube(int slices);

// A fish of length 1 in the local frame of DrawInstances: head at z = 0, tail tip at z = −1, +y
// up, +x to its side. A streamlined body of revolution with flattened sides, a forked tail fin, a
// dorsal fin and (detail ≥ 1) two pectoral fins; fins are thin closed lenses, so the whole is
// closed. Countershaded: per-vertex colours darker on the back than the belly. Detail 0 has 64
// triangles (a distant copy), 1 about 270, each further step more rings and slices.
TriMesh makeFishMesh(int detail);

}  // namespace reel
