// How a robot reader (URDF, MJCF) loads a mesh file its model names: given the file name relative
// to the model, the mesh, or why not. The scene reader supplies it (asset roots, caps).
#pragma once

#include <functional>
#include <memory>
#include <string>

#include "core/error.h"
#include "core/mesh.h"

namespace reel::io {

using MeshLoader = std::function<Result<std::shared_ptr<const TriMesh>>(const std::string& filename)>;

}  // namespace reel::io
