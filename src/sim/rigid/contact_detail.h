// Internal to the rigid narrow phase (sim/rigid/contact*.cpp): feature ids, small buffers,
// candidate points and their reduction to a manifold, the Gauss-map arcs of polytope edges.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include "sim/rigid/contact.h"

namespace reel::contact_detail {

using Index = std::size_t;
inline constexpr double kInf = std::numeric_limits<double>::infinity();

// Feature ids: the top two bits say which kind of contact, the rest name its features.
//   face contacts: reference face (8 bits), incident face (8 bits), clipped point (14 bits:
//                  the labels of the polygon edges before and after it, 7 bits each);
//   edge pairs:    A's edge (15 bits), B's edge (15 bits);
//   rounded cores: the face (8 bits) and which end of a segment (1, 2; 0 for a single point).
inline constexpr std::uint32_t kIdFaceA = 0u << 30, kIdFaceB = 1u << 30, kIdEdges = 2u << 30,
                        kIdRound = 3u << 30;

inline std::uint32_t faceId(std::uint32_t kind, int ref, int inc, std::uint32_t feature) {
  return kind | (static_cast<std::uint32_t>(ref) & 0xFFu) << 22 |
         (static_cast<std::uint32_t>(inc) & 0xFFu) << 14 | (feature & 0x3FFFu);
}

// A list with room for N elements in place and on the heap beyond: the usual polytope (a box's
// 8 vertices, a clipped quad's 8 points) costs no allocation.
template <class T, int N>
class SmallBuf {
 public:
  SmallBuf() = default;
  SmallBuf(const SmallBuf&) = delete;
  SmallBuf& operator=(const SmallBuf&) = delete;
  int size() const { return n_; }
  void clear() { n_ = 0; }
  void push(const T& x) {
    if (n_ == cap_) grow(2 * cap_);
    data_[n_++] = x;
  }
  T& operator[](int i) { return data_[i]; }
  const T& operator[](int i) const { return data_[i]; }

 private:
  void grow(int cap) {
    std::vector<T> bigger(static_cast<Index>(cap));
    std::copy(data_, data_ + n_, bigger.begin());
    heap_.swap(bigger);
    data_ = heap_.data();
    cap_ = cap;
  }
  std::array<T, N> inline_;
  std::vector<T> heap_;
  T* data_ = inline_.data();
  int n_ = 0, cap_ = N;
};

// A contact point before the manifold is reduced: position and depth in a working frame.
struct Candidate {
  Vec3 x;
  double depth;
  std::uint32_t id;
};
using Candidates = SmallBuf<Candidate, 64>;


inline const Vec3& vertexOf(const ConvexPolytope& p, int i) { return p.vertices[static_cast<Index>(i)]; }
// The polytope with its edges' faces: itself, or a completed copy in `tmp` (hand-made polytopes).
const ConvexPolytope& withEdgeFaces(const ConvexPolytope& p, ConvexPolytope& tmp);
// The largest distance of a vertex from the local origin, m: the scale of tolerances.
double polytopeExtent(const ConvexPolytope& p);
// At most 4 of the candidates (indices, ascending), areas measured in the plane normal to n.
int reduceToFour(const Candidates& c, const Vec3& n, std::array<int, 4>& pick);
// The manifold from candidates in a frame (R, p) with normal n in that frame.
bool emit(const Candidates& c, const Mat3& R, const Vec3& p, const Vec3& n, Manifold& out);

// The Gauss map of an edge (the normals of the planes touching the polytope along it): the arc
// from face normal n0 to n1; where the two faces are back to back (a flat polytope) half a
// circle, split at the outward normal in their plane. `dir` is the edge as face 0's loop walks it.
struct EdgeArcs {
  std::array<Vec3, 2> from, to;
  std::array<Vec3, 2> plane;  // from × to: the normal of each arc's great circle
  int count;
  Vec3 mid;  // a direction inside the arcs
};
EdgeArcs edgeArcs(const Vec3& n0, const Vec3& n1, const Vec3& dir);
// The arcs through the opposite normals (the Gauss map of −P); their planes are the same.
EdgeArcs negated(EdgeArcs g);
// Whether two edges' arcs cross (their edge pair is a face of the Minkowski difference).
bool arcsCross(const EdgeArcs& g, const EdgeArcs& h);
// The arcs of edge e of P, given P's face normals and the edge's direction in the working frame.
EdgeArcs edgeArcsOf(const ConvexPolytope& P, int e, const Vec3* normals, const Vec3& dir);

// Polytope against polytope (contact_polytope.cpp).
bool polytopePair(const ConvexPolytope& A, double rA, const Pose& pa, const ConvexPolytope& B, double rB,
                  const Pose& pb, double margin, Manifold& out);

}  // namespace reel::contact_detail
