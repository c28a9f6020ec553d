// DrawList: the plain list of things to draw in one frame (MuJoCo's mjvScene, Box2D's debug draw
// table). The simulation fills it, the renderer only reads it: triangle meshes, instanced
// spheres, tubes (lines), camera, lights and materials — never a cloth, a fish or a fluid.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/image.h"
#include "core/light.h"
#include "core/mesh.h"
#include "core/types.h"

namespace reel {

struct DrawMaterial {
  Vec3 color{0.8, 0.8, 0.8};  // linear albedo
  std::shared_ptr<const Image> texture;  // sRGB pixels, multiplied into the albedo (UVs)
  double specular = 0.0, shininess = 32.0, opacity = 1.0;
  bool double_sided = false;  // sheets: lit from both sides
  bool checker = false;       // checkerboard of `color` and a darker shade, 0.5 m squares
};

struct DrawMesh {
  // Static geometry is shared between frames (the renderer keeps its GPU copy while the pointer
  // is alive); geometry that changes every frame is a new mesh each frame.
  std::shared_ptr<const TriMesh> mesh;
  bool per_frame = false;  // true: new geometry every frame (uploaded each time)
  DrawMaterial material;
};

struct DrawSpheres {
  std::vector<float> centers;  // xyz per sphere, m
  std::vector<float> colors;   // linear rgb per sphere, multiplied into the albedo (may be empty)
  float radius = 0.02f;        // m
  DrawMaterial material;
};

// Tubes of one radius between point pairs (springs).
struct DrawTubes {
  std::vector<float> ends;  // 6 floats per tube: x0 y0 z0 x1 y1 z1, m
  float radius = 0.005f;
  DrawMaterial material;
};

struct DrawCamera {
  Vec3 position{0, 1, 5}, target{0, 0, 0}, up{0, 1, 0};
  double fov_deg = 40.0;  // vertical
};

struct DrawList {
  DrawCamera camera;
  std::vector<LightDesc> lights;  // exactly these shine
  Vec3 background_top{0.8, 0.85, 0.9}, background_bottom{0.8, 0.85, 0.9};
  Vec3 fog_color{0.5, 0.6, 0.7};
  double fog_density = 0.0;
  std::string tonemap = "none";
  std::vector<DrawMesh> meshes;
  std::vector<DrawSpheres> spheres;
  std::vector<DrawTubes> tubes;
  void clearGeometry() {
    meshes.clear();
    spheres.clear();
    tubes.clear();
  }
};

}  // namespace reel
