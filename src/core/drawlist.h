// DrawList: the plain list of things to draw in one frame (MuJoCo's mjvScene, Box2D's debug draw
// table). The simulation fills it, the renderer only reads it: triangle meshes, instanced
// spheres, tubes (lines), instanced meshes, camera, lights and materials — never a cloth, a fish or a fluid.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/brdf.h"
#include "core/environment.h"
#include "core/image.h"
#include "core/light.h"
#include "core/mesh.h"
#include "core/types.h"

namespace reel {

// A physically based material (docs/rendering.md, "Shading"): Lambert diffuse and a GGX specular
// lobe, plus an optional sheen. specular = 0 and metallic = 0 is exactly Lambert.
struct DrawMaterial {
  Vec3 color{0.8, 0.8, 0.8};  // linear albedo (a metal's specular colour)
  std::shared_ptr<const Image> texture;  // sRGB pixels, multiplied into the albedo (UVs)
  // Relief (bump mapping over the UVs): a height map, its pixels' luminance read as stored (0..1,
  // no sRGB decoding), and the height of luminance 1 over 0 (m; 0: flat). It may be `texture` itself.
  std::shared_ptr<const Image> bump;
  double bump_depth = 0.0;  // m
  // Creases that come and go (Oat 2007, "Animated wrinkle maps"): a second height map over the
  // UVs, as `bump`, its depth (m; the height of luminance 1 over 0) scaled per vertex by the
  // mesh's `wrinkle` weights.
  std::shared_ptr<const Image> wrinkles;
  double wrinkle_depth = 0.0;  // m
  double wrinkle_shade = 0.0;  // 0..1: a crease's floor this much darker in full (less light reaches into a fold)
  // specular 0..1: a dielectric's reflectance at normal incidence is 0.08·specular (Burley 2012;
  // 0.5 is 4%, water and glass). roughness 0..1 (α = roughness²); none: from the Blinn–Phong
  // `shininess` of older scenes, brdf::roughnessOfShininess.
  double specular = 0.0, shininess = 32.0, opacity = 1.0;
  std::optional<double> roughness;
  double metallic = 0.0;  // 0..1: 1 reflects in its albedo's colour and has no diffuse term
  double sheen = 0.0;     // 0..1: cloth's soft rim of fibres catching grazing light
  // 0..1: how much of what lies behind shows through the surface (water, glass), refracted and
  // absorbed along the depth of the body: light keeps albedo^(depth / absorption_depth) of itself.
  double transmission = 0.0, absorption_depth = 0.1;  // —, m
  double roughnessValue() const;
  // Skin: light scattered under the surface (pre-integrated skin shading, Penner & Borshukov
  // 2011, with d'Eon & Luebke's 2007 diffusion profile of skin; brdf::integrateSkin). Each
  // colour's diffuse term is the table's D(n·l, scatter·1/r) for the surface's curvature 1/r at
  // the pixel: 1 is skin at the scene's metres, larger widens the profile by that factor (a
  // stylised or enlarged body), 0 is Lambert. Such a surface takes a light's shadow only where it
  // faces the light, and the shadow's penumbra reddens.
  double scatter = 0.0;
  // 0..1: of the light arriving from behind a thin sheet of skin (an ear), the share that passes
  // through it, reddened by the tissue (skin lets red through, absorbs blue), unshadowed; needs
  // double_sided and scatter (ignored without them).
  double translucency = 0.0;
  bool double_sided = false;  // sheets: lit from both sides
  // double_sided: the back's albedo (the side the normal points away from), plain (no texture);
  // none: the back looks like the front.
  std::optional<Vec3> back_color;
  bool checker = false;       // checkerboard of `color` and a darker shade, squares checker_size m wide
  double checker_size = 0.5;  // m
  // false: left out of the shadow maps (specks whose shadows no one sees: foam, spray's streaks).
  bool casts_shadow = true;
  // With opacity below 1: blended as one solid turned translucent, only the nearest of all such
  // surfaces at a pixel (the renderer lays down their depth first, after the other blended ones).
  // Without it every surface is blended, the far ones and those inside a body too.
  bool front_only = false;
};

inline double DrawMaterial::roughnessValue() const { return roughness ? *roughness : brdf::roughnessOfShininess(shininess); }

struct DrawMesh {
  // Static geometry is shared between frames (the renderer keeps its GPU copy while the pointer
  // is alive); geometry that changes every frame is a new mesh each frame.
  std::shared_ptr<const TriMesh> mesh;
  bool per_frame = false;  // true: new geometry every frame (uploaded each time)
  DrawMaterial material;
  int source = -1;  // the World's body that drew it (motion blur pairs frames' items by it); −1: none
};

struct DrawSpheres {
  std::vector<float> centers;  // xyz per sphere, m
  std::vector<float> colors;   // linear rgb per sphere, multiplied into the albedo (may be empty)
  float radius = 0.02f;        // m
  DrawMaterial material;
  int source = -1;  // the World's body that drew it (motion blur pairs frames' items by it); −1: none
};

// Tubes of one radius between point pairs (springs).
struct DrawTubes {
  std::vector<float> ends;  // 6 floats per tube: x0 y0 z0 x1 y1 z1, m
  float radius = 0.005f;
  DrawMaterial material;
  int source = -1;  // the World's body that drew it (motion blur pairs frames' items by it); −1: none
};

// One mesh drawn many times (a school of fish), each copy placed by its own transform and tinted
// by its own colour, optionally bent by a travelling wave (a swimming body's undulation).
//
// The mesh is authored in local coordinates: +z forward (the head), +y up, +x to the side; its
// tail lies toward −z. Copy i draws each local vertex p as  origin_i + X_i·p'.x + Y_i·p'.y + Z_i·p'.z
// where p' is p with its sideways coordinate displaced by the wave
//   p'.x = p.x + a(p.z)·sin(phase_i − wave_number·(wave_start − p.z)),
//   a(z) = wave_amplitude·s², s = clamp((wave_start − z)/(wave_start − wave_end), 0, 1),
// i.e. nothing ahead of wave_start, growing quadratically to wave_amplitude at wave_end (the tail
// tip). Normals follow the bend. With `phases` empty, no copy bends.
//
// Copies farther than `far_distance` from the camera are drawn with `far_mesh` when it is set (a
// level of detail for small, distant copies); the wave bends both the same way.
//
// The renderer: normals go through the inverse transpose of [X Y Z], so any invertible transform
// lights correctly; the wave needs wave_end < wave_start (else no bend). Meshes are taken as
// closed, counter-clockwise from outside: back faces are culled unless material.double_sided
// (give double_sided to open meshes and to mirroring transforms, det [X Y Z] < 0). Each mesh
// costs one draw call for all its copies; on llvmpipe the time goes by triangles drawn, so a far
// mesh of few triangles is what makes thousands of copies cheap.
struct DrawInstances {
  std::shared_ptr<const TriMesh> mesh;      // local coordinates as above
  std::shared_ptr<const TriMesh> far_mesh;  // optional coarser version of `mesh`
  double far_distance = 0.0;                // m; 0 or no far_mesh: always `mesh`
  // 12 floats per copy: X (3), Y (3), Z (3), origin (3). X, Y, Z are the local axes in world
  // space and carry the copy's scale; a rigid placement has them orthonormal times a scale.
  std::vector<float> transforms;
  std::vector<float> colors;  // linear rgb per copy, multiplied into the albedo (may be empty)
  std::vector<float> phases;  // wave phase per copy, radians (may be empty: no wave)
  float wave_amplitude = 0.0f;  // sideways displacement at wave_end, mesh units
  float wave_number = 0.0f;     // radians per mesh unit along z
  float wave_start = 0.0f, wave_end = -1.0f;  // local z where the bend starts and is full
  DrawMaterial material;
  int source = -1;  // the World's body that drew it (motion blur pairs frames' items by it); −1: none
  std::size_t count() const { return transforms.size() / 12; }
};

struct DrawCamera {
  Vec3 position{0, 1, 5}, target{0, 0, 0}, up{0, 1, 0};
  double fov_deg = 40.0;  // vertical
  // Depth of field (core/motion.h): the lens' diameter (m; 0: a pinhole) and the distance in
  // focus along the view (m; 0: the target's), and the pictures averaged over the lens.
  double aperture = 0.0, focus_distance = 0.0;
  int lens_samples = 8;
};

struct DrawList {
  DrawCamera camera;
  std::vector<LightDesc> lights;  // exactly these shine
  Vec3 background_top{0.8, 0.85, 0.9}, background_bottom{0.8, 0.85, 0.9};
  BackgroundGlow background_glow;
  Vec3 fog_color{0.5, 0.6, 0.7};
  double fog_density = 0.0;
  std::string tonemap = "none";  // none | aces
  double exposure = 0.0;          // EV: the linear picture is scaled by 2^exposure before tone mapping
  // Image-based light (and the background, if it says so); none: only `lights`.
  std::shared_ptr<const Environment> environment;
  // Screen-space ambient occlusion of the ambient and environment light: the distance it looks
  // for occluders (m; 0: none) and an exponent that deepens it.
  double ao_radius = 0.0, ao_strength = 1.0;
  std::vector<DrawMesh> meshes;
  std::vector<DrawSpheres> spheres;
  std::vector<DrawTubes> tubes;
  std::vector<DrawInstances> instances;
  // Motion blur (core/motion.h): the shutter angle (deg; 0: none), the pictures averaged over
  // it, and the draw list of the frame before, whose geometry the shutter opens on (null: the
  // first frame, or no blur).
  double shutter_deg = 0.0;
  int shutter_samples = 5;
  std::shared_ptr<const DrawList> previous;
  // Seconds between the frames (0: unknown): what a body that draws its fastest parts as streaks
  // (a liquid's spray) takes the exposure from.
  double frame_time = 0.0;
  void clearGeometry() {
    meshes.clear();
    spheres.clear();
    tubes.clear();
    instances.clear();
  }
};

}  // namespace reel
