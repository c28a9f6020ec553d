// What an object gives the renderer: its shape as a mesh, authored in world space (moving objects
// are carried to their pose by the World each frame).
#pragma once

#include "core/drawlist.h"
#include "core/scene/object.h"

namespace reel {

DrawMesh objectMesh(const ObjectDesc& o);

}  // namespace reel
