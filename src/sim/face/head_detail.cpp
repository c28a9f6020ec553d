// reel's head drawn finer than it is simulated (SkinDetail, head.h): the simulated skin's grid
// refined, its fine points on the head's own shape at rest, carried by the tissue's motion.
#include <algorithm>
#include <cmath>

#include "core/math.h"
#include "core/mesh.h"
#include "core/parallel.h"
#include "sim/face/head.h"
#include "sim/face/head_shape.h"
#include "sim/face/head_tone.h"

namespace reel {

namespace {

// Each vertex's normal (area-weighted) and the frame of it and its first edge.
std::vector<Mat3> frames(std::span<const Vec3> x, const std::vector<std::uint32_t>& tris) {
  const std::vector<Vec3> normal = areaNormals(x, tris);
  std::vector<Vec3> edge(x.size(), Vec3::Zero());
  for (std::size_t t = 0; t + 2 < tris.size(); t += 3) {
    const std::uint32_t a = tris[t], b = tris[t + 1], c = tris[t + 2];
    for (auto [v, w] : {std::pair{a, b}, std::pair{b, c}, std::pair{c, a}})
      if (edge[v].isZero()) edge[v] = x[w] - x[v];
  }
  std::vector<Mat3> out(x.size());
  for (std::size_t k = 0; k < x.size(); ++k) {
    const Vec3 n = unitOr(normal[k], Vec3::UnitY());
    const Vec3 t = unitOr(edge[k] - edge[k].dot(n) * n, perpendicular(n));
    out[k].col(0) = t;
    out[k].col(1) = n.cross(t);
    out[k].col(2) = n;
  }
  return out;
}

}  // namespace

SkinDetail makeSkinDetail(const FaceSurface& s, int level) {
  SkinDetail out;
  const int C = s.columns, R = s.rays, rows = s.rows, m = std::max(level, 1);
  if (!s.generated || C < 3 || R < 2 || s.polar.size() < static_cast<std::size_t>(R * C)) return out;
  const auto top = std::uint32_t{0}, bottom = static_cast<std::uint32_t>(s.lower_lip > 0 ? s.lower_lip - 1 : s.size() - 1);
  // The simulated skin's vertex at grid row j (0: the crown, rows: the bottom), column i; in the
  // band below the parting its top row is the lower lip's.
  auto coarse = [&](int j, int i, bool lower) {
    if (j <= 0) return top;
    if (j >= rows) return bottom;
    const auto v = static_cast<std::uint32_t>(1 + (j - 1) * C + ((i % C) + C) % C);
    return lower && j == s.parting_row ? s.lower_copy[v] : v;
  };
  const double ym = s.parting_y;
  // The head's own skin at fractional row f (up to the last ring of rays) and column g: its
  // polar angle blended from the grid's (which keeps the rings in order), the shape exact.
  auto shape = [&](double f, double g) {
    const int j = std::min(static_cast<int>(f), R - 2), i = static_cast<int>(g);
    const double a = f - j, b = g - i;
    auto P = [&](int jj, int ii) { return jj == 0 ? 0.0 : s.polar[static_cast<std::size_t>(jj * C + ((ii % C) + C) % C)]; };
    const double th = (1 - a) * ((1 - b) * P(j, i) + b * P(j, i + 1)) + a * ((1 - b) * P(j + 1, i) + b * P(j + 1, i + 1));
    const Vec3 d = head::direction(th, head::atIndex(s.phi, g));
    return Vec3(s.scale * head::skinPoint(head::baseRadius(d, s.look) * d, d, ym, s.look));
  };
  // Fine rows J = 0 .. rows·m; the first and last are the crown's and the bottom's vertex.
  const int J_end = rows * m, W = C * m;
  std::vector<std::uint32_t> index(static_cast<std::size_t>((J_end + 1) * W)), lower_index(static_cast<std::size_t>(W));
  auto point = [&](int J, int I, bool lower) {
    SkinDetail::Point p;
    const int j = J / m, i = I / m;
    const double a = static_cast<double>(J % m) / m, b = static_cast<double>(I % m) / m;
    // The quad's corners: a band's top row is the lower lip's below the parting (and on the
    // parting's row itself for a lower copy).
    const bool low_top = lower || (j == s.parting_row && J % m != 0);
    p.from = {coarse(j, i, low_top), coarse(j, i + 1, low_top), coarse(j + 1, i, false), coarse(j + 1, i + 1, false)};
    p.w = {(1 - a) * (1 - b), (1 - a) * b, a * (1 - b), a * b};
    Vec3 blend = Vec3::Zero();
    float u = 0, v = 0;
    for (int c = 0; c < 4; ++c) {
      blend += p.w[static_cast<std::size_t>(c)] * s.skin[p.from[static_cast<std::size_t>(c)]];
      u += static_cast<float>(p.w[static_cast<std::size_t>(c)]) * s.uv[p.from[static_cast<std::size_t>(c)]][0];
      v += static_cast<float>(p.w[static_cast<std::size_t>(c)]) * s.uv[p.from[static_cast<std::size_t>(c)]][1];
    }
    p.uv = {u, v};
    // Over the rays' rings the head's shape; below them (the neck's rings, hidden by the collar
    // but for their top) the blend.
    if (J > 0 && J <= (R - 1) * m) p.offset = shape(static_cast<double>(J) / m, static_cast<double>(I) / m) - blend;
    const Vec3 tint = head::skinTint((blend + p.offset) / s.scale);
    p.tint = {static_cast<float>(tint.x()), static_cast<float>(tint.y()), static_cast<float>(tint.z())};
    return p;
  };
  // The fine points' places first (cheap), then their offsets in parallel (each on its own).
  struct Slot {
    int J, I;
    bool lower;
  };
  std::vector<Slot> slots;
  auto add = [&](int J, int I, bool lower) {
    slots.push_back({J, I, lower});
    return static_cast<std::uint32_t>(slots.size() - 1);
  };
  for (int J = 0; J <= J_end; ++J) {
    if (J == 0 || J == J_end) {
      const std::uint32_t v = add(J, 0, false);
      for (int I = 0; I < W; ++I) index[static_cast<std::size_t>(J * W + I)] = v;
      continue;
    }
    for (int I = 0; I < W; ++I) index[static_cast<std::size_t>(J * W + I)] = add(J, I, false);
    if (J != s.parting_row * m) continue;
    // The parting: a lower copy wherever a corner of the edge it lies on has one.
    for (int I = 0; I < W; ++I) {
      const int i = I / m;
      const bool split = s.lower_copy[coarse(s.parting_row, i, false)] != coarse(s.parting_row, i, false) ||
                         (I % m != 0 && s.lower_copy[coarse(s.parting_row, i + 1, false)] != coarse(s.parting_row, i + 1, false));
      lower_index[static_cast<std::size_t>(I)] = split ? add(J, I, true) : index[static_cast<std::size_t>(J * W + I)];
    }
  }
  out.points.resize(slots.size());
  parallelFor(static_cast<std::ptrdiff_t>(slots.size()), [&](std::ptrdiff_t k) {
    const Slot& sl = slots[static_cast<std::size_t>(k)];
    out.points[static_cast<std::size_t>(k)] = sl.J == J_end ? SkinDetail::Point{{bottom, bottom, bottom, bottom}, {1, 0, 0, 0}, Vec3::Zero(),
                                                                                 s.uv[bottom]}
                                                            : point(sl.J, sl.I, sl.lower);
  });
  // Triangles as the simulated skin's: diagonals mirrored about the midline.
  auto at = [&](int J, int I, bool lower) {
    I = ((I % W) + W) % W;
    return lower ? lower_index[static_cast<std::size_t>(I)] : index[static_cast<std::size_t>(J * W + I)];
  };
  auto tri = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) { out.tris.insert(out.tris.end(), {a, b, c}); };
  for (int J = 0; J < J_end; ++J)
    for (int I = 0; I < W; ++I) {
      const bool low = J == s.parting_row * m;
      const std::uint32_t a = at(J, I, low), b = at(J, I + 1, low), c = at(J + 1, I, false), d = at(J + 1, I + 1, false);
      if (J == 0) tri(a, c, d);
      else if (J + 1 == J_end) tri(a, c, b);
      else if (I < W / 2) tri(a, d, b), tri(a, c, d);
      else tri(a, c, b), tri(b, c, d);
    }
  // How far the fine skin dips below each simulated vertex's rest surface.
  const std::vector<Mat3> f = frames(s.skin, s.tris);
  out.dip.assign(s.size(), 0.0);
  for (const SkinDetail::Point& p : out.points)
    for (int c = 0; c < 4; ++c)
      if (p.w[static_cast<std::size_t>(c)] > 0) {
        const std::uint32_t v = p.from[static_cast<std::size_t>(c)];
        out.dip[v] = std::max(out.dip[v], -p.offset.dot(f[v].col(2)));
      }
  return out;
}


void SkinDetail::place(std::span<const Vec3> rest, std::span<const Vec3> posed, std::span<const Vec3> x,
                       const std::vector<std::uint32_t>& coarse_tris, int smoothing, std::vector<Vec3>& out,
                       std::vector<Vec3>* relaxed) const {
  // Displacements from the posed rest, relaxed over the triangles' edges (each edge once per triangle
  // side: a neighbour's weight is how many triangles the two share).
  const std::size_t n = x.size();
  std::vector<Vec3> u(n), sum(n), now(x.begin(), x.end());
  std::vector<double> count(n);
  for (std::size_t k = 0; k < n; ++k) u[k] = x[k] - posed[k];
  for (int pass = 0; pass < smoothing; ++pass) {
    std::fill(sum.begin(), sum.end(), Vec3::Zero());
    std::fill(count.begin(), count.end(), 0.0);
    for (std::size_t q = 0; q + 2 < coarse_tris.size(); q += 3)
      for (int e = 0; e < 3; ++e) {
        const std::uint32_t a = coarse_tris[q + static_cast<std::size_t>(e)], b = coarse_tris[q + static_cast<std::size_t>((e + 1) % 3)];
        sum[a] += u[b], sum[b] += u[a];
        count[a] += 1, count[b] += 1;
      }
    for (std::size_t k = 0; k < n; ++k)
      if (count[k] > 0) u[k] = 0.5 * (u[k] + sum[k] / count[k]);
  }
  if (smoothing > 0)
    for (std::size_t k = 0; k < n; ++k) now[k] = posed[k] + u[k];
  if (relaxed) *relaxed = now;
  const std::vector<Mat3> f0 = frames(rest, coarse_tris), f1 = frames(now, coarse_tris);
  out.resize(points.size());
  for (std::size_t k = 0; k < points.size(); ++k) {
    const Point& p = points[k];
    Vec3 q = Vec3::Zero();
    for (int c = 0; c < 4; ++c) {
      const std::uint32_t v = p.from[static_cast<std::size_t>(c)];
      const double w = p.w[static_cast<std::size_t>(c)];
      if (w != 0) q += w * (now[v] + f1[v] * (f0[v].transpose() * p.offset));
    }
    out[k] = q;
  }
}

double SkinDetail::blend(const Point& p, std::span<const double> value) const {
  double v = 0;
  for (int c = 0; c < 4; ++c) v += p.w[static_cast<std::size_t>(c)] * value[p.from[static_cast<std::size_t>(c)]];
  return v;
}

std::vector<std::vector<std::uint32_t>> openEdgeNeighbours(const std::vector<std::uint32_t>& tris, std::size_t vertices) {
  std::vector<std::pair<std::uint32_t, std::uint32_t>> edges;
  for (std::size_t k = 0; k + 2 < tris.size(); k += 3)
    for (int e = 0; e < 3; ++e) {
      const std::uint32_t a = tris[k + static_cast<std::size_t>(e)], b = tris[k + static_cast<std::size_t>((e + 1) % 3)];
      edges.emplace_back(std::min(a, b), std::max(a, b));
    }
  std::sort(edges.begin(), edges.end());
  std::vector<std::vector<std::uint32_t>> out(vertices);
  for (std::size_t i = 0; i < edges.size(); ++i) {
    const bool shared = (i > 0 && edges[i - 1] == edges[i]) || (i + 1 < edges.size() && edges[i + 1] == edges[i]);
    const auto [a, b] = edges[i];
    if (shared || a == b) continue;
    out[a].push_back(b);
    out[b].push_back(a);
  }
  return out;
}

}  // namespace reel
