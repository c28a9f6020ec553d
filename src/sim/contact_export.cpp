// What bodies hand the contact layer (sim/contact_layer.h): their points, triangles, threads and
// convex parts, appended to the layer's flat arrays with checks on what they index.
#include <algorithm>

#include "core/error.h"
#include "sim/body.h"
#include "sim/contact_layer.h"

namespace reel {

void ContactProxies::clear() {
  x.clear();
  v.clear();
  x0.clear();
  w.clear();
  r.clear();
  piece.clear();
  slot.clear();
  tri.clear();
  edge.clear();
  gone.clear();
  material.clear();
  surfaces.clear();
  x0_given.clear();
  convex.clear();
  body.clear();
  first.assign(1, 0);
  tri_first.assign(1, 0);
}

std::uint32_t ContactProxies::add(const Body& b, std::size_t index, std::uint32_t base_piece) {
  body.push_back(index);
  surfaces.emplace_back();
  x0_given.push_back(0);
  ContactExport out(*this);
  out.base_piece_ = base_piece;
  b.exportContacts(out);
  material.resize(x.size(), -1);
  x0.resize(x.size());
  first.push_back(static_cast<std::uint32_t>(x.size()));
  tri_first.push_back(static_cast<std::uint32_t>(tri.size()));
  return out.pieces_;
}

void ContactExport::points(std::span<const Vec3> x, std::span<const Vec3> v, std::span<const double> inv_mass,
                           double radius, std::span<const int> piece) {
  REEL_CHECK(x.size() == v.size() && x.size() == inv_mass.size() && (piece.empty() || piece.size() == x.size()),
             "contact points: arrays of different sizes");
  REEL_CHECK(p_.x.size() == p_.first.back(), "contact points handed twice by one body");
  const auto slot = static_cast<std::uint32_t>(p_.body.size() - 1);
  p_.x.insert(p_.x.end(), x.begin(), x.end());
  p_.v.insert(p_.v.end(), v.begin(), v.end());
  p_.w.insert(p_.w.end(), inv_mass.begin(), inv_mass.end());
  p_.r.insert(p_.r.end(), x.size(), radius);
  p_.slot.insert(p_.slot.end(), x.size(), slot);
  std::uint32_t pieces = 1;
  for (std::size_t i = 0; i < x.size(); ++i) {
    const auto k = piece.empty() ? 0u : static_cast<std::uint32_t>(std::max(piece[i], 0));
    p_.piece.push_back(base_piece_ + k);
    pieces = std::max(pieces, k + 1);
  }
  pieces_ = pieces;
}

void ContactExport::triangle(int a, int b, int c) {
  const std::uint32_t f = p_.first.back(), n = static_cast<std::uint32_t>(p_.x.size()) - f;
  REEL_CHECK(a >= 0 && b >= 0 && c >= 0 && static_cast<std::uint32_t>(std::max({a, b, c})) < n,
             "contact triangle over a point the body did not hand");
  const std::array<std::uint32_t, 3> t{f + static_cast<std::uint32_t>(a), f + static_cast<std::uint32_t>(b),
                                       f + static_cast<std::uint32_t>(c)};
  p_.tri.push_back(t);
}

void ContactExport::edge(int a, int b) {
  const std::uint32_t f = p_.first.back(), n = static_cast<std::uint32_t>(p_.x.size()) - f;
  REEL_CHECK(a >= 0 && b >= 0 && a != b && static_cast<std::uint32_t>(std::max(a, b)) < n,
             "contact edge over a point the body did not hand");
  p_.edge.push_back({f + static_cast<std::uint32_t>(a), f + static_cast<std::uint32_t>(b)});
}

void ContactExport::starts(std::span<const Vec3> x0) {
  const std::uint32_t f = p_.first.back();
  REEL_CHECK(x0.size() == p_.x.size() - f && !p_.x0_given.back(), "contact starts: not one per point, or handed twice");
  p_.x0.resize(f);
  p_.x0.insert(p_.x0.end(), x0.begin(), x0.end());
  p_.x0_given.back() = 1;
}

void ContactExport::surfaces(std::span<const Surface> table, int materials, std::span<const double> range,
                             std::span<const int> material) {
  const std::uint32_t f = p_.first.back();
  const std::size_t n = p_.x.size() - f;
  REEL_CHECK(materials > 0 && range.size() == static_cast<std::size_t>(materials) &&
                 table.size() % static_cast<std::size_t>(materials) == 0 && material.size() == n,
             "contact surfaces: a table, ranges or materials of the wrong size");
  REEL_CHECK(p_.material.size() == f, "contact surfaces handed twice by one body");
  for (int m : material) {
    REEL_CHECK(m >= -1 && m < materials, "contact surfaces: a point of no material");
    p_.material.push_back(m);
  }
  p_.surfaces.back() = {table, materials, range};
}

const Surface& ContactProxies::surfaceOf(std::uint32_t i, std::size_t k, const Surface& own, double& range) const {
  const std::int32_t m = material[i];
  const Surfaces& s = surfaces[slot[i]];
  const std::size_t row = k * static_cast<std::size_t>(s.materials) + static_cast<std::size_t>(m);
  if (m < 0 || row >= s.table.size()) {
    range = 0.0;
    return own;
  }
  const Surface& sf = s.table[row];
  range = sf.adhesion > 0.0 ? s.range[static_cast<std::size_t>(m)] : 0.0;
  return sf;
}

void ContactExport::convex(const ConvexShape& shape, const Pose& pose, const Vec3& v, const Vec3& w, double inv_mass,
                           const Mat3& inv_inertia, std::size_t collider) {
  p_.convex.push_back({&shape, pose, v, w, inv_mass, inv_inertia, collider, body_, pose.p});
}

}  // namespace reel
