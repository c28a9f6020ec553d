// From the scene straight to the draw list, without passing through the simulation: the camera
// at a time, the lights (or the default rig), the background, fog and tone mapping.
#pragma once

#include "core/camera.h"
#include "core/drawlist.h"
#include "core/scene.h"

namespace reel {

// Without a `lights` list: a warm key light with soft shadows and a cool, soft ambient.
std::vector<LightDesc> defaultLights();

// Sets everything but the geometry of `out` for the scene at time t (s). `rig`: the World's
// camera rig, when the scene's camera follows or frames a body (World::cameraRig()).
void setSceneView(const SceneDesc& scene, double t, DrawList& out, const CameraRig* rig = nullptr);

}  // namespace reel
