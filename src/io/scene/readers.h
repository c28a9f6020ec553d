// The body kinds' scene readers, one per kind (io/scene/<kind>.cpp). The registry of kinds
// (app/body_kinds.cpp) pairs each with its scene name and its builder.
#pragma once

#include <memory>

#include "core/scene.h"
#include "io/scene_loader.h"

namespace reel::io {

std::shared_ptr<const BodyParams> readMassSpringBody(Obj& o, BodyDesc& body, const SceneDesc& scene);
std::shared_ptr<const BodyParams> readRopeBody(Obj& o, BodyDesc& body, const SceneDesc& scene);
std::shared_ptr<const BodyParams> readNetBody(Obj& o, BodyDesc& body, const SceneDesc& scene);
std::shared_ptr<const BodyParams> readLatticeBody(Obj& o, BodyDesc& body, const SceneDesc& scene);
std::shared_ptr<const BodyParams> readClothBody(Obj& o, BodyDesc& body, const SceneDesc& scene);
std::shared_ptr<const BodyParams> readFluidBody(Obj& o, BodyDesc& body, const SceneDesc& scene);
std::shared_ptr<const BodyParams> readSchoolBody(Obj& o, BodyDesc& body, const SceneDesc& scene);
std::shared_ptr<const BodyParams> readFishBody(Obj& o, BodyDesc& body, const SceneDesc& scene);
std::shared_ptr<const BodyParams> readFoodBody(Obj& o, BodyDesc& body, const SceneDesc& scene);
std::shared_ptr<const BodyParams> readSeaweedBody(Obj& o, BodyDesc& body, const SceneDesc& scene);

}  // namespace reel::io
