// What a school gives the renderer: one instanced fish mesh (reel's own, or the scene's `mesh`),
// each agent placed along its heading, tinted, its tail beating at its own phase.
#include "sim/draw_material.h"
#include "sim/school/school_body.h"

namespace reel {

void SchoolBody::draw(DrawList&) const {}

}  // namespace reel
