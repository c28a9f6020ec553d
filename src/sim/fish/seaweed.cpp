#include "sim/fish/seaweed.h"

#include <cmath>

#include "core/math.h"
#include "core/random.h"
#include "sim/draw_material.h"
#include "sim/water.h"

namespace reel {

void SeaweedBody::step(StepContext& ctx) {
  const MassSpringModel& m = net_.model;
  // In water: buoyancy, and drag toward the water's velocity (without water, neither).
  const bool water = ctx.water && ctx.water->density() > 0;
  if (lift_.size() != m.nodes()) {
    lift_.resize(m.nodes());
    for (std::size_t i = 0; i < m.nodes(); ++i) lift_[i] = -desc_.buoyancy * m.mass[i] * m.gravity;
  }
  net_.system->setExternalForces(water ? lift_.data() : nullptr);
  net_.integrate(ctx);
  // The drag implicitly per node: (m + hc) v' = m v + hc u.
  auto& x = net_.state.x;
  auto& v = net_.state.v;
  const double c = water ? desc_.drag : 0.0, h = ctx.h;
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (m.fixed[i]) continue;
    const Vec3 u = ctx.water ? ctx.water->at(x[i], ctx.t1, *ctx.colliders) : Vec3::Zero();
    const Vec3 vn = (m.mass[i] * v[i] + h * c * u) / (m.mass[i] + h * c);
    x[i] += h * (vn - v[i]);
    v[i] = vn;
  }
  net_.contacts(ctx);
}

// Each strand a ribbon (a kelp blade) through its nodes, narrowing to the tip.
void SeaweedBody::draw(DrawList& out) const {
  auto mesh = std::make_shared<TriMesh>();
  const auto& x = net_.state.x;
  const std::size_t per = static_cast<std::size_t>(desc_.segments) + 1;
  for (std::size_t s = 0; s < strands(); ++s) {
    const auto base = static_cast<std::uint32_t>(mesh->vertexCount());
    for (std::size_t j = 0; j < per; ++j) {
      const std::size_t i = s * per + j;
      const Vec3 along = (x[s * per + std::min(j + 1, per - 1)] - x[s * per + (j == 0 ? 0 : j - 1)]).normalized();
      // The blade twists up the strand (and each strand starts at its own angle), so it shows
      // its face from every side.
      const Vec3 e1 = perpendicular(along), e2 = along.cross(e1);
      const double turn = 2.39996 * static_cast<double>(s) + 0.45 * static_cast<double>(j);
      const Vec3 side = std::cos(turn) * e1 + std::sin(turn) * e2;
      // Narrowing to the tip.
      const double w = 0.5 * desc_.width * (1.0 - 0.6 * static_cast<double>(j) / static_cast<double>(per - 1));
      const Vec3 n = side.cross(along).normalized();
      const double v = static_cast<double>(j) / static_cast<double>(per - 1);
      mesh->addVertex(x[i] - w * side, n, 0, v);
      mesh->addVertex(x[i] + w * side, n, 1, v);
    }
    for (std::uint32_t j = 0; j + 1 < per; ++j) {
      const std::uint32_t a = base + 2 * j;
      mesh->indices.insert(mesh->indices.end(), {a, a + 1, a + 3, a, a + 3, a + 2});
    }
  }
  DrawMesh dm;
  dm.mesh = std::move(mesh);
  dm.per_frame = true;
  dm.material = drawMaterial(material_);
  dm.material.double_sided = true;
  out.meshes.push_back(std::move(dm));
}

Result<std::unique_ptr<Body>> buildSeaweedBody(const BodyDesc& desc, const BuildContext& ctx) {
  const auto& d = desc.as<SeaweedDesc>();
  std::vector<Vec3> bases = d.bases;
  for (long long k = 0; d.bases.empty() && k < d.count; ++k) {
    const auto i = static_cast<std::uint64_t>(k);
    bases.push_back(Vec3(d.min.x() + uniformAt(ctx.seed, 0x5EA, 3 * i) * (d.max.x() - d.min.x()), d.min.y(),
                         d.min.z() + uniformAt(ctx.seed, 0x5EA, 3 * i + 1) * (d.max.z() - d.min.z())));
  }
  MassSpringDesc ms;
  std::vector<std::array<int, 2>> edges;  // each stalk's stretch springs: the threads it meets others with
  const int n = d.segments;
  for (std::size_t s = 0; s < bases.size(); ++s) {
    const double height = d.height * (1.0 - d.height_variation * uniformAt(ctx.seed, 0x5EA, 3 * s + 2));
    const double m = d.mass / (n + 1), seg = height / n;
    const int first = static_cast<int>(ms.nodes.size());
    for (int j = 0; j <= n; ++j) {
      NodeDesc nd;
      nd.position = bases[s] + Vec3(0, seg * j, 0);
      nd.mass = m;
      nd.fixed = j == 0;
      ms.nodes.push_back(nd);
    }
    // Stretch springs between neighbours, bend springs across two; damped at a tenth of critical.
    const double damping = 0.2 * std::sqrt(d.stiffness * m);
    for (int j = 0; j < n; ++j) {
      ms.springs.push_back({first + j, first + j + 1, d.stiffness, damping, -1.0});
      edges.push_back({first + j, first + j + 1});
    }
    for (int j = 0; j + 2 <= n; ++j) ms.springs.push_back({first + j, first + j + 2, 0.25 * d.stiffness, damping, -1.0});
  }
  auto body = std::make_unique<SeaweedBody>(desc.name, d, desc.material);
  if (Status st = buildNetwork(*body, ms, desc, ctx, 0.5 * d.width); !st) return st.error();
  body->setEdges(std::move(edges));
  // Each stalk a piece of its own (the contact layer looks only at stalks near something).
  std::vector<int> stalk(ms.nodes.size());
  for (std::size_t k = 0; k < stalk.size(); ++k) stalk[k] = static_cast<int>(k / static_cast<std::size_t>(n + 1));
  body->setSurface({}, std::move(stalk));
  return std::unique_ptr<Body>(std::move(body));
}

}  // namespace reel
