// What a springs body gives the renderer: its nodes as spheres, its springs as tubes (a rope's as
// thick as its nodes: one continuous tube), or a lattice's smooth skin.
#include "sim/draw_material.h"
#include "sim/springs/springs_body.h"

namespace reel {

void SpringsBody::draw(DrawList& out) const {
  const std::vector<Vec3>& x = net_.state.x;
  if (skin_) {  // over the nodes' spheres: the skin lies on the floor where they do
    out.meshes.push_back({skin_->mesh(x, net_.radius), true, drawMaterial(material_)});
    return;
  }
  DrawSpheres nodes;
  nodes.radius = static_cast<float>(net_.radius);
  nodes.material = drawMaterial(material_);
  appendPoints(nodes.centers, x);
  DrawTubes springs;
  // A rope is one continuous tube as thick as its nodes (they round its bends); a net or lattice
  // shows its springs as thinner struts between the knots.
  springs.radius = static_cast<float>((generator() == "rope" ? 1.0 : 0.35) * net_.radius);
  springs.material = nodes.material;
  const Springs& s = net_.model.springs;
  springs.ends.reserve(6 * s.size());
  for (std::size_t k = 0; k < s.size(); ++k)
    for (const Vec3* p : {&x[static_cast<std::size_t>(s.a[k])], &x[static_cast<std::size_t>(s.b[k])]})
      for (int c = 0; c < 3; ++c) springs.ends.push_back(static_cast<float>((*p)[c]));
  out.spheres.push_back(std::move(nodes));
  if (!springs.ends.empty()) out.tubes.push_back(std::move(springs));
}

}  // namespace reel
