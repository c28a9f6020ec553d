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
  convex.clear();
  body.clear();
  first.assign(1, 0);
  tri_first.assign(1, 0);
}

std::uint32_t ContactProxies::add(const Body& b, std::size_t index, std::uint32_t base_piece) {
  body.push_back(index);
  ContactExport out(*this);
  out.base_piece_ = base_piece;
  b.exportContacts(out);
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

void ContactExport::convex(const ConvexShape& shape, const Pose& pose, const Vec3& v, const Vec3& w, double inv_mass,
                           const Mat3& inv_inertia, std::size_t collider) {
  p_.convex.push_back({&shape, pose, v, w, inv_mass, inv_inertia, collider, body_, pose.p});
}

}  // namespace reel
