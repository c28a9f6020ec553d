// Generators of the seed's 1-D, 2-D and 3-D mass-spring-damper systems. Each builds the same
// explicit nodes-and-springs description as a `mass_spring` body, so one engine runs them all.
#pragma once

#include "core/scene/mass_spring.h"

namespace reel {

MassSpringDesc buildRope(const RopeDesc& d);
MassSpringDesc buildNet(const NetDesc& d);
MassSpringDesc buildLattice(const LatticeDesc& d);
// The lattice's outer faces as quads of node indices, counter-clockwise seen from outside (the
// control mesh of its skin).
std::vector<std::array<int, 4>> latticeSkin(const LatticeDesc& d);

}  // namespace reel
