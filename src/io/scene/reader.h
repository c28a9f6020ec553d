// What the scene readers share (io-internal): ranges, appearance, node lists, spring keys, the
// placement of a sheet, lists of entries. Each body kind's reader is in io/scene/<kind>.cpp.
#pragma once

#include <array>
#include <string>
#include <utility>
#include <vector>

#include "core/scene.h"
#include "core/scene/mass_spring.h"
#include "core/scene/school.h"
#include "io/json_reader.h"
#include "io/scene_loader.h"

namespace reel::io {

inline const Range kPos = Range::positive();
inline const Range kNonNeg = Range::nonNegative();
inline const Range kUnit = Range::closed(0.0, 1.0);
inline const Range kLength{0.0, 1e4, true, false};  // a length that must be positive, m

// Appearance (stored for the renderer): color, texture or pattern, specular, shininess, opacity.
void readMaterial(Obj& o, Material& m);

// How many items of `item_bytes` fit in `fraction` of this machine's memory, clamped to [lo, hi]
// (`fallback` when the memory size is unknown): the default caps of particles and agents.
long long itemsInMemory(double fraction, long long item_bytes, long long lo, long long hi, long long fallback);

// The mesh file named by `key` (resolved among the allowed folders and imported now), or nullptr
// with an error naming the key; `file` gets the name as written.
std::shared_ptr<const TriMesh> readMeshFile(Obj& o, const std::string& key, bool required, std::string* file = nullptr);

// A unit heading under `key`: any non-zero vector, normalised (absent: nullopt).
std::optional<Vec3> readHeading(Obj& o, const std::string& key);

// A group's `start` ({center, radius} or {min, max}) and its `heading` (both keys of o).
void readStart(Obj& o, StartRegion& start);

// A box ({min, max}) or ball ({center, radius}) that agents or fish keep inside, with its margin.
void readBounds(Obj& o, SchoolBoundsDesc& b);

// An imported mesh: its file (resolved and imported now), placement (`position`, `rotation_deg`)
// and `scale` (a number or one per axis).
MeshObjectShape readMeshShape(Obj& o);
// `motion`: keyframes of the reference point's position and the rotation.
void readMotion(Obj& o, ObjectDesc& ob);
// `surface`, with per-species surfaces for liquids.
void readSurfaces(Obj& o, Surface& surface, SpeciesSurfaces& species_surface);

// An object of type `type` (one of kObjectTypes).
void readObject(Obj& o, ObjectDesc& ob, const std::string& type);
inline const std::vector<std::string> kObjectTypes = {"plane", "sphere", "box", "capsule", "mesh", "container"};

// Named nodes of a generator: a name → its node (or a group: a corner, an edge) as grid coordinates.
using NodeNames = std::vector<std::pair<std::string, std::vector<long long>>>;

// Reads a list of nodes (`pinned`, a grip's `nodes`): each entry a node index (negative counts
// from the end), a grid coordinate list of `dims` indices, or a name of one node or a group
// (a corner, an edge). Writes resolved node indices.
void readPins(Obj& o, const std::vector<long long>& dims, long long nodes, const NodeNames& names,
              std::vector<int>& out, const std::string& key = "pinned", bool required = false);

// A generator's total mass shared by its nodes must leave each a usable mass.
void checkNodeMass(Obj& o, double mass, long long nodes);

// A spring family's stiffness and damping keys; without a fallback the stiffness is required.
SpringParams readSpring(Obj& o, const std::string& stiff_key, const std::string& damp_key, const SpringParams* fallback);

// The placement keys of a sheet (net or cloth): position, rotation, size and resolution.
void readSheet(Obj& o, Vec3& position, Vec3& rotation_deg, std::array<double, 2>& size, std::array<int, 2>& resolution);

// The corners of an nx × ny sheet by name.
NodeNames cornerNames(long long nx, long long ny);

// Reads the list `key` of objects, calling f(Obj&) for each entry (then checking its keys).
template <class F>
void readList(Obj& o, const std::string& key, F&& f, bool required = false) {
  const Json* j = o.raw(key);
  const std::string p = childPath(o.path(), key);
  if (!j) {
    if (required && o.ok()) o.diag().error(p, "missing required key");
    return;
  }
  if (!j->is_array()) {
    o.diag().error(p, "expected a list, got " + typeName(*j));
    return;
  }
  for (std::size_t k = 0; k < j->size(); ++k) {
    Obj e((*j)[k], childPath(p, k), o.diag());
    f(e);
    e.finish();
  }
}

// A sub-object `key` of o, read by f(Obj&) and then checked for unknown keys.
template <class F>
void readObjectKey(Obj& o, const std::string& key, F&& f) {
  if (const Json* j = o.raw(key)) {
    Obj sub(*j, childPath(o.path(), key), o.diag());
    f(sub);
    sub.finish();
  }
}

}  // namespace reel::io
