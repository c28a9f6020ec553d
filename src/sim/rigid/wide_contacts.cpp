// The passes over a wide contact (sim/rigid/solver_detail.h): four contacts of one colour, a lane
// each, gathered from the dense velocities and places, solved, and scattered back.
#include <cmath>

#include "sim/rigid/solver_detail.h"

namespace reel::rigid_detail {
namespace {

// The four lanes' body velocities, gathered from the dense array and scattered back.
struct alignas(32) WideMotion {
  L3 va, wa, vb, wb;
  [[gnu::always_inline]] WideMotion(const WideContact& c, const std::vector<Motion>& motion) {
    for (int l = 0; l < 4; ++l) {
      if (c.a[static_cast<std::size_t>(l)] >= 0) {
        const Motion& A = motion[static_cast<std::size_t>(c.a[static_cast<std::size_t>(l)])];
        setLane(va, l, A.v), setLane(wa, l, A.w);
      }
      if (c.b[static_cast<std::size_t>(l)] >= 0) {
        const Motion& B = motion[static_cast<std::size_t>(c.b[static_cast<std::size_t>(l)])];
        setLane(vb, l, B.v), setLane(wb, l, B.w);
      }
    }
  }
  [[gnu::always_inline]] void store(const WideContact& c, std::vector<Motion>& motion) const {
    for (int l = 0; l < 4; ++l) {
      if (c.a[static_cast<std::size_t>(l)] >= 0) {
        Motion& A = motion[static_cast<std::size_t>(c.a[static_cast<std::size_t>(l)])];
        A.v = lane(va, l), A.w = lane(wa, l);
      }
      if (c.b[static_cast<std::size_t>(l)] >= 0) {
        Motion& B = motion[static_cast<std::size_t>(c.b[static_cast<std::size_t>(l)])];
        B.v = lane(vb, l), B.w = lane(wb, l);
      }
    }
  }
  // B's point velocity less A's along d (an object's surface moves at vs; B's terms are zero).
  [[gnu::always_inline]] Lane4 along(const WidePoint& p, const WideAxis& x, const L3& d) const {
    return dot(d, vb + p.vs - va) + dot(x.jb, wb) - dot(x.ja, wa);
  }
  // Impulses l1 along d1 and l2 along d2 on B (A takes the opposite).
  [[gnu::always_inline]] void apply(const WideContact& c, const WideAxis& x1, const L3& d1, const Lane4& l1,
                                    const WideAxis& x2, const L3& d2, const Lane4& l2) {
    const L3 P = l1 * d1 + l2 * d2;
    va = va - c.ima * P, wa = wa - (l1 * x1.ia + l2 * x2.ia);
    vb = vb + c.imb * P, wb = wb + (l1 * x1.ib + l2 * x2.ib);
  }
  [[gnu::always_inline]] void apply(const WideContact& c, const WideAxis& x, const L3& d, const Lane4& l) {
    va = va - (c.ima * l) * d, wa = wa - l * x.ia;
    vb = vb + (c.imb * l) * d, wb = wb + l * x.ib;
  }
};

// The four lanes' bodies' rotations and centres now (an object: the identity and zero, its
// anchor being in the world already).
struct alignas(32) WidePlace {
  std::array<L3, 3> ra, rb;  // rows
  L3 xa, xb;
  [[gnu::always_inline]] WidePlace(const WideContact& c, const std::vector<Place>& place) {
    for (int l = 0; l < 4; ++l) {
      const int ia = c.a[static_cast<std::size_t>(l)], ib = c.b[static_cast<std::size_t>(l)];
      if (ia < 0) continue;
      const Place& A = place[static_cast<std::size_t>(ia)];
      const Place B = ib >= 0 ? place[static_cast<std::size_t>(ib)] : Place{};
      for (int r = 0; r < 3; ++r) setLane(ra[static_cast<std::size_t>(r)], l, A.R.row(r)), setLane(rb[static_cast<std::size_t>(r)], l, B.R.row(r));
      setLane(xa, l, A.x), setLane(xb, l, B.x);
    }
  }
  [[gnu::always_inline]] static L3 turn(const std::array<L3, 3>& R, const L3& v) { return {dot(R[0], v), dot(R[1], v), dot(R[2], v)}; }
};

}  // namespace

// Last step's impulses applied again (warm start).
REEL_CLONED void warmStart(const WideContact& c, const WidePoint* pts, std::vector<Motion>& motion) {
  WideMotion m(c, motion);
  for (int k = 0; k < c.count; ++k) {
    const WidePoint& p = pts[k];
    m.apply(c, p.n, c.n, p.ln);
    m.apply(c, p.t1, c.t1, p.lt1, p.t2, c.t2, p.lt2);
  }
  m.store(c, motion);
}

// One pass over a contact's points, in order: the normal (a separated point may close its gap
// this sub-step; an overlap beyond the slop is pushed out softly when `push`), then friction in
// the circle of radius μ·λ_n. A point's separation now (negative: overlap) follows from how far
// its two anchors moved apart along the normal since the step began.
REEL_CLONED void solveContact(const WideContact& c, WidePoint* pts, std::vector<Motion>& motion,
                              const std::vector<Place>& place, double h, const Soft& soft, bool push) {
  WideMotion m(c, motion);
  const WidePlace at(c, place);
  const Lane4 zero = splat(0.0), one = splat(1.0);
  const Lane4 push_rate = splat(push ? soft.bias_rate : 0.0), push_mass = splat(push ? soft.mass_scale : 1.0);
  const Lane4 push_impulse = splat(push ? soft.impulse_scale : 0.0), max_push = splat(push ? -kMaxPush : 0.0);
  for (int k = 0; k < c.count; ++k) {
    WidePoint& p = pts[k];
    const L3 d = (at.xb + WidePlace::turn(at.rb, p.lb)) - (at.xa + WidePlace::turn(at.ra, p.la));
    const Lane4 s = dot(d, c.n) + p.base + p.slop;
    const Lane4 pushed = push_rate * s;
    const auto apart = s > zero;
    const Lane4 bias = apart ? s / h : (pushed > max_push ? pushed : max_push);
    const Lane4 mass_scale = apart ? one : push_mass, impulse_scale = apart ? zero : push_impulse;
    const Lane4 vn = m.along(p, p.n, c.n);
    Lane4 ln = p.ln - p.n.mass * mass_scale * (vn + bias) - impulse_scale * p.ln;
    ln = ln > zero ? ln : zero;
    m.apply(c, p.n, c.n, ln - p.ln);
    p.ln = ln;
    const Lane4 l1 = p.lt1 - p.t1.mass * m.along(p, p.t1, c.t1);
    const Lane4 l2 = p.lt2 - p.t2.mass * m.along(p, p.t2, c.t2);
    const Lane4 lim = c.mu * p.ln, q = l1 * l1 + l2 * l2;
    Lane4 len;
    for (int l = 0; l < 4; ++l) len[l] = std::sqrt(q[l]);
    const Lane4 scale = (len > lim) & (len > zero) ? lim / len : one;
    const Lane4 d1 = l1 * scale - p.lt1, d2 = l2 * scale - p.lt2;
    p.lt1 += d1;
    p.lt2 += d2;
    m.apply(c, p.t1, c.t1, d1, p.t2, c.t2, d2);
  }
  m.store(c, motion);
}

// Restitution: a point that was approaching faster than kBounceSpeed leaves at e times that speed.
void bounce(const WideContact& c, WidePoint* pts, std::vector<Motion>& motion) {
  const Lane4 zero = splat(0.0);
  if (!((c.e > zero)[0] | (c.e > zero)[1] | (c.e > zero)[2] | (c.e > zero)[3])) return;
  WideMotion m(c, motion);
  for (int k = 0; k < c.count; ++k) {
    WidePoint& p = pts[k];
    const auto hit = (c.e > zero) & (p.vn0 <= splat(-kBounceSpeed)) & (p.ln > zero);
    Lane4 ln = p.ln - p.n.mass * (m.along(p, p.n, c.n) + c.e * p.vn0);
    ln = hit ? (ln > zero ? ln : zero) : p.ln;
    m.apply(c, p.n, c.n, ln - p.ln);
    p.ln = ln;
  }
  m.store(c, motion);
}

}  // namespace reel::rigid_detail
