// MJCF (MuJoCo's XML) models as articulated bodies, the common subset: one tree of <body>
// elements under <worldbody>, each with pos and quat / euler / axisangle / zaxis; its joints (none:
// welded to its parent; one `hinge` or `ball`; two hinges through one point: a universal joint;
// `free` or <freejoint/> on the root) with axis, pos, range (a hinge's limits, a ball's cone),
// damping and armature; one <geom> (sphere, capsule, box, cylinder, mesh; size or fromto; pos and
// orientation; mass or density) and an optional <inertial> (pos, quat, mass, diaginertia or
// fullinertia). <compiler
// angle> is honoured. <option>, <visual>, <statistic>, <size>, <asset>, <actuator>, <sensor>,
// <keyframe>, <contact>, and <site>, <camera>, <light> and <geom> directly under <worldbody> are
// passed over. <default> classes cascade (nested classes, `class`, a body's `childclass`) onto
// joints, geoms and meshes. A `mesh` geom names an <asset> <mesh file scale> (an OBJ/STL/... below
// <compiler meshdir>, relative to the model): drawn as the mesh, met as its convex hull, its mass
// from its closed volume at the geom's density unless given. Anything else (a `slide` joint,
// <tendon>, <equality>, two geoms in a body, `coordinate="global"`) is refused, named, with its line.
#pragma once

#include <vector>

#include "core/error.h"
#include "core/scene/articulated.h"
#include "io/scene/mesh_loader.h"
#include "io/xml.h"

namespace reel::io {

// The model's links, parents first, in its root body's frame (see urdfLinks). `root_offset`: the
// root's centre of mass from the root body's frame; `free_root`: the root has a free joint (else
// it is welded to the world). `mesh` loads a mesh file named relative to the model.
Result<std::vector<ArticulatedLinkDesc>> mjcfLinks(const XmlElement& mujoco, Vec3& root_offset, bool& free_root,
                                                   const MeshLoader& mesh);

}  // namespace reel::io
