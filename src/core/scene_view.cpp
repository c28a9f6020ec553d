#include "core/scene_view.h"

#include "core/camera.h"

namespace reel {

std::vector<LightDesc> defaultLights() {
  LightDesc key;
  key.kind = LightKind::Directional;
  key.direction = Vec3(-0.45, -1.0, -0.35);
  key.color = Vec3(1.0, 0.96, 0.9);
  key.intensity = 1.1;
  key.shadows = true;
  LightDesc amb;
  amb.kind = LightKind::Ambient;
  amb.color = Vec3(0.55, 0.62, 0.75);
  amb.intensity = 0.45;
  return {key, amb};
}

void setSceneView(const SceneDesc& scene, double t, DrawList& out, const CameraRig* rig) {
  const RenderDesc& r = scene.render;
  out.camera = rig && rig->active ? rigCamera(scene.camera, *rig, t, static_cast<double>(r.width) / r.height)
                                  : cameraAt(scene.camera, t);
  out.lights = scene.has_lights ? scene.lights : defaultLights();
  out.background_top = r.background_top;
  out.background_bottom = r.background_bottom;
  out.background_glow = r.background_glow;
  out.fog_color = r.fog_color;
  out.fog_density = r.fog_density;
  out.tonemap = r.tonemap;
  out.exposure = r.exposure;
  out.environment = r.environment.maps;
  out.ao_radius = r.ao_radius;
  out.ao_strength = r.ao_strength;
  out.shutter_deg = r.shutter_deg;
  out.shutter_samples = r.shutter_samples;
}

}  // namespace reel
