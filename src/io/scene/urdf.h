// URDF robot descriptions as articulated bodies (the common subset): links with <inertial>
// (origin, mass, inertia) and one <collision> (else <visual>) geometry (box, sphere, cylinder,
// capsule, mesh: drawn as itself, met as its convex hull) with its origin; joints `revolute` (hinge with limits), `continuous` (hinge) and
// `fixed`, with origin, axis, limit and dynamics damping. <material>, <gazebo>, <transmission>,
// <calibration> and <safety_controller> do not change the dynamics and are passed over. Anything
// else (a `prismatic`, `floating` or `planar` joint, <mimic>, a package:// mesh, an unknown element) is
// refused, named, with its line.
#pragma once

#include <vector>

#include "core/error.h"
#include "core/scene/articulated.h"
#include "io/scene/mesh_loader.h"
#include "io/xml.h"

namespace reel::io {

// The links of the robot, in the frame of its root link (parents first; frames aligned with the
// root's at the zero pose, each at its centre of mass). `root_offset`: the root's centre of mass
// from the root link's frame. Errors: BadInput, "line N: ...".
// `mesh`: loads a <mesh filename> (relative to the URDF's folder), or says why not.
Result<std::vector<ArticulatedLinkDesc>> urdfLinks(const XmlElement& robot, Vec3& root_offset, const MeshLoader& mesh);

}  // namespace reel::io
