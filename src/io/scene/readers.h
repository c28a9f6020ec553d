// The body kinds' scene readers, one per kind (io/scene/<kind>.cpp). The registry of kinds
// (app/body_kinds.cpp) pairs each with its scene name and its builder.
#pragma once

#include <memory>

#include "core/scene.h"
#include "core/scene/rigid.h"
#include "io/json_reader.h"
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
std::shared_ptr<const BodyParams> readRigidBody(Obj& o, BodyDesc& body, const SceneDesc& scene);
std::shared_ptr<const BodyParams> readFaceBody(Obj& o, BodyDesc& body, const SceneDesc& scene);
std::shared_ptr<const BodyParams> readArticulatedBody(Obj& o, BodyDesc& body, const SceneDesc& scene);

// The rigid body that moves the scene's object `index` (`"dynamic": true`, its `mass`); a shape
// without a finite solid (an open mesh) is reported at the object's path.
std::shared_ptr<const RigidDesc> rigidFromObject(const ObjectDesc& ob, std::size_t index, Diagnostics& d);

}  // namespace reel::io
