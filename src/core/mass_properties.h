// Mass, centre of mass and inertia tensor of solids: exact for triangulated polyhedra (Mirtich's
// algorithm), with a check that a triangle mesh bounds a solid; closed forms for the primitives.
#pragma once

#include <array>
#include <span>

#include "core/error.h"
#include "core/mesh.h"
#include "core/types.h"

namespace reel {

struct MassProperties {
  double volume = 0;             // m³
  double mass = 0;               // kg
  Vec3 center_of_mass{0, 0, 0};  // m, in the mesh's frame
  Mat3 inertia = Mat3::Zero();   // kg·m², about the centre of mass, mesh axes; full tensor, I_xy = −∫xy dm
};

// Mirtich, "Fast and Accurate Computation of Polyhedral Mass Properties", JGT 1(2), 1996:
// volume integrals by the divergence theorem reduced to face integrals, reduced to projection
// integrals. Exact for polyhedra. The triangles index `vertices`, counter-clockwise seen from
// outside, and must close the solid (solidMassProperties checks that); zero-area triangles add
// nothing. Uniform `density`, kg/m³.
MassProperties polyhedronMass(std::span<const Vec3> vertices, std::span<const std::array<int, 3>> triangles,
                              double density);

// Checks a triangle mesh is a valid solid, then polyhedronMass. The vertices are welded by exact
// position first (imported meshes repeat them per triangle). Refused (BadInput, the message naming
// the problem with a count and an example) unless: positions are finite and indices in range; no
// triangle has zero area; the mesh is closed (every edge shared by exactly two triangles, with
// opposite orientation); it winds outward (each shell's signed volume positive, or negative for a
// cavity inside material; inside out is named as such); no two triangles that share no vertex
// cross (sweep and prune along the longest axis of the bounds, then an exact-sign test; faces that
// only touch, e.g. two boxes stacked, do not count); and density is positive and finite.
Result<MassProperties> solidMassProperties(const TriMesh& mesh, double density);

// A body's properties carried to where it is placed (x ↦ R·x + t): the centre moves, the inertia
// turns (R·I·Rᵀ).
MassProperties placed(MassProperties m, const Mat3& R, const Vec3& t);
// The sum of parts, about their common centre of mass (parallel axes).
MassProperties combined(std::span<const MassProperties> parts);
// The same shape at another total mass, kg (the inertia scales with it).
MassProperties withMass(MassProperties m, double mass);

// Closed forms, centred at the origin, diagonal inertia. A sphere of radius r; a box of full size;
// a capsule of segment length L along y and radius r (a cylinder and two hemispheres); a cylinder
// of radius r and height H along y. Lengths m, density kg/m³.
MassProperties sphereMass(double r, double density);
MassProperties boxMass(const Vec3& size, double density);
MassProperties capsuleMass(double length, double r, double density);
MassProperties cylinderMass(double r, double height, double density);

}  // namespace reel
