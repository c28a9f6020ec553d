#include "sim/face/tissue.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

#include "core/parallel.h"
#include "sim/forces.h"

namespace reel {

using Index = std::ptrdiff_t;

namespace {

// The prism's volume by the divergence theorem, V = Σ over its boundary's triangles of
// a·(b × c)/6, each side quad (not flat in general) taken as the mean of its two splits into
// triangles, so the volume is the same function for a prism listed in any order (a mirrored
// prism gives the mirrored forces). That mean, ½([P,Q,R] + [P,R,S] + [P,Q,S] + [Q,R,S]) for the
// quad PQRS, is ¼ Σ·((R − P) × (S − Q)) with Σ = P + Q + R + S (the bilinear patch's volume):
// three cross products for the quad and its gradient instead of twelve. Points relative to their
// centroid; `grad`, when given, gets ∂V/∂p for each of the six points.
double prismVolumeGrad(const std::array<Vec3, 6>& p, std::array<Vec3, 6>* grad) {
  Vec3 c = Vec3::Zero();
  for (const Vec3& q : p) c += q;
  c /= 6.0;
  std::array<Vec3, 6> r;
  for (int i = 0; i < 6; ++i) r[static_cast<std::size_t>(i)] = p[static_cast<std::size_t>(i)] - c;
  auto at = [](int i) { return static_cast<std::size_t>(i); };
  // The lower triangle (a0, a2, a1), facing down, and the upper (b0, b1, b2), facing up.
  const Vec3 lo = r[2].cross(r[1]), up = r[4].cross(r[5]);
  double v = r[0].dot(lo) + r[3].dot(up);
  // The side quads (a_i, a_j, b_j, b_i), j = i + 1, facing out: P = a_i, Q = a_j, R = b_j,
  // S = b_i, A = R − P, B = S − Q; its gradient ¼(A×B − B×Σ) at P, ¼(A×B + B×Σ) at R,
  // ¼(A×B − Σ×A) at Q, ¼(A×B + Σ×A) at S.
  Vec3 AB[3], BS[3], SA[3];
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3;
    const Vec3 A = r[at(3 + j)] - r[at(i)], B = r[at(3 + i)] - r[at(j)];
    const Vec3 sum = r[at(i)] + r[at(j)] + r[at(3 + j)] + r[at(3 + i)];
    AB[i] = A.cross(B);
    v += 0.25 * sum.dot(AB[i]);
    if (grad) BS[i] = B.cross(sum), SA[i] = sum.cross(A);
  }
  if (grad) {
    // Each corner's gradient written once (from its triangle and the two quads it is in: a_k is P
    // of quad k and Q of quad k − 1, b_k is S of quad k and R of quad k − 1).
    const Vec3 lo_grad[3] = {lo, r[0].cross(r[2]), r[1].cross(r[0])};
    const Vec3 up_grad[3] = {up, r[5].cross(r[3]), r[3].cross(r[4])};
    for (int k = 0; k < 3; ++k) {
      const int b = (k + 2) % 3;  // the quad before
      (*grad)[at(k)] = (lo_grad[k] + 0.25 * (AB[k] - BS[k] + AB[b] - SA[b])) / 6.0;
      (*grad)[at(3 + k)] = (up_grad[k] + 0.25 * (AB[k] + SA[k] + AB[b] + BS[b])) / 6.0;
    }
  }
  return v / 6.0;
}

}  // namespace

double prismVolume(const std::array<Vec3, 6>& p) { return prismVolumeGrad(p, nullptr); }

// Jacobi passes per step: each node's correction is the mean of its elements', so it takes a few
// passes to reach the constraints' solution.
constexpr int kVolumePasses = 3;
// Each node's mean correction is over-relaxed (Macklin et al.'s averaging with a factor above 1):
// fewer passes for the same volume, still a fraction of the summed corrections.
constexpr double kRelaxation = 1.8;
static void volumePass(FaceTissue& T, const MassSpringModel& m, std::vector<Vec3>& x, std::vector<Vec3>& v, double h);

void indexCorners(FaceTissue& T, std::size_t nodes) {
  T.corner_start.assign(nodes + 1, 0);
  for (const auto& P : T.prisms)
    for (int c : P) ++T.corner_start[static_cast<std::size_t>(c) + 1];
  for (std::size_t i = 0; i < nodes; ++i) T.corner_start[i + 1] += T.corner_start[i];
  T.corners.assign(6 * T.prisms.size(), 0);
  T.corner_prism.assign(6 * T.prisms.size(), 0);
  std::vector<int> fill(T.corner_start.begin(), T.corner_start.end() - 1);
  for (std::size_t e = 0; e < T.prisms.size(); ++e)
    for (int c = 0; c < 6; ++c) {
      const auto q = static_cast<std::size_t>(fill[static_cast<std::size_t>(T.prisms[e][static_cast<std::size_t>(c)])]++);
      T.corners[q] = static_cast<int>(6 * e) + c;
      T.corner_prism[q] = static_cast<int>(e);
    }
  T.active.resize(T.prisms.size());
  for (std::size_t e = 0; e < T.prisms.size(); ++e) T.active[e] = static_cast<int>(e);
}

void keepActive(FaceTissue& T, const MassSpringDesc& ms) {
  T.active.clear();
  for (std::size_t e = 0; e < T.prisms.size(); ++e)
    for (int c : T.prisms[e])
      if (!ms.nodes[static_cast<std::size_t>(c)].fixed) {
        T.active.push_back(static_cast<int>(e));
        break;
      }
}

MassSpringDesc buildTissue(const FaceSurface& s, const FaceDesc& desc, FaceTissue& T) {
  const std::size_t n = s.size();
  T = FaceTissue{};
  T.n = n;
  T.volume_modulus = desc.volume_modulus;
  T.biphasic_strain = desc.biphasic_strain;
  T.biphasic_ratio = desc.biphasic_ratio;
  // The fascia lies below the dermal–fatty layer: the same share of the way to the bone everywhere.
  const double share = desc.dermis.thickness / (desc.dermis.thickness + desc.muscle.thickness);
  std::vector<Vec3> x(3 * n);
  T.out.resize(n);
  T.floor_fascia.resize(n);
  T.floor_skin.resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    x[k] = s.skin[k];
    x[n + k] = s.skin[k] + share * (s.bone[k] - s.skin[k]);
    x[2 * n + k] = s.bone[k];
    const double depth = (s.skin[k] - s.bone[k]).norm();
    T.out[k] = (s.skin[k] - s.bone[k]) / depth;
    T.floor_fascia[k] = 0.25 * (1 - share) * depth;
    T.floor_skin[k] = 0.25 * depth;
  }
  // Springs, keyed by their ends, their stiffness summed over the elements they belong to.
  std::map<std::pair<int, int>, double> springs;
  auto add = [&](int a, int b, double k) {
    if (a > b) std::swap(a, b);
    springs[{a, b}] += k;
  };
  auto len2 = [&](int a, int b) { return (x[static_cast<std::size_t>(a)] - x[static_cast<std::size_t>(b)]).squaredNorm(); };
  std::vector<double> mass(3 * n, 0.0);
  for (std::size_t t = 0; t + 2 < s.tris.size(); t += 3) {
    const int v[3] = {static_cast<int>(s.tris[t]), static_cast<int>(s.tris[t + 1]), static_cast<int>(s.tris[t + 2])};
    // The epidermis: a membrane of thickness t and modulus E, k = E t A / l² per triangle at an edge.
    const double area = 0.5 * (x[static_cast<std::size_t>(v[1])] - x[static_cast<std::size_t>(v[0])])
                                   .cross(x[static_cast<std::size_t>(v[2])] - x[static_cast<std::size_t>(v[0])])
                                   .norm();
    for (int e = 0; e < 3; ++e) {
      const int a = v[e], b = v[(e + 1) % 3];
      add(a, b, desc.epidermis.modulus * desc.epidermis.thickness * area / len2(a, b));
    }
    // Two prisms: dermal (fascia below, epidermis above) and muscle (bone below, fascia above).
    for (int layer = 0; layer < 2; ++layer) {
      const int lo = layer == 0 ? static_cast<int>(n) : static_cast<int>(2 * n), hi = layer == 0 ? 0 : static_cast<int>(n);
      std::array<int, 6> P{lo + v[0], lo + v[1], lo + v[2], hi + v[0], hi + v[1], hi + v[2]};
      std::array<Vec3, 6> p;
      for (int c = 0; c < 6; ++c) p[static_cast<std::size_t>(c)] = x[static_cast<std::size_t>(P[static_cast<std::size_t>(c)])];
      const double V = prismVolume(p);
      if (!(V > 0)) continue;  // a degenerate element (a pole's sliver) adds nothing
      T.prisms.push_back(P);
      T.rest_volume.push_back(V);
      for (int c = 0; c < 6; ++c) mass[static_cast<std::size_t>(P[static_cast<std::size_t>(c)])] += desc.density * V / 6.0;
      // Its springs: the three edges below and above, straight down, and crosswise (two per side
      // face), each taking E·V/(5 l²): fifteen springs that give the element about modulus E.
      const double E = layer == 0 ? desc.dermis.modulus : desc.muscle.modulus;
      auto spring = [&](int a, int b) { add(a, b, E * V / (5.0 * len2(a, b))); };
      for (int e = 0; e < 3; ++e) {
        const int f = (e + 1) % 3;
        spring(P[static_cast<std::size_t>(e)], P[static_cast<std::size_t>(f)]);
        spring(P[static_cast<std::size_t>(3 + e)], P[static_cast<std::size_t>(3 + f)]);
        spring(P[static_cast<std::size_t>(e)], P[static_cast<std::size_t>(3 + e)]);
        spring(P[static_cast<std::size_t>(e)], P[static_cast<std::size_t>(3 + f)]);
        spring(P[static_cast<std::size_t>(f)], P[static_cast<std::size_t>(3 + e)]);
      }
    }
  }
  // Skin resists bending, which a membrane does not: flexion springs across each edge of the
  // epidermis, between the two vertices opposite it (Provot 1995), at a fifth of the membrane's
  // stiffness over the two triangles. Without them a fold the brows press into the skin can snap through and stay when
  // the muscles let go.
  {
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::pair<int, double>> opposite;  // edge → (vertex, area)
    for (std::size_t t = 0; t + 2 < s.tris.size(); t += 3) {
      const std::uint32_t v[3] = {s.tris[t], s.tris[t + 1], s.tris[t + 2]};
      const double area = 0.5 * (s.skin[v[1]] - s.skin[v[0]]).cross(s.skin[v[2]] - s.skin[v[0]]).norm();
      for (int e = 0; e < 3; ++e) {
        const std::pair<std::uint32_t, std::uint32_t> key = std::minmax(v[e], v[(e + 1) % 3]);
        const int c = static_cast<int>(v[(e + 2) % 3]);
        auto [it, fresh] = opposite.emplace(key, std::pair{c, area});
        if (!fresh && it->second.first != c)
          add(it->second.first, c, 0.2 * desc.epidermis.modulus * desc.epidermis.thickness * 0.5 * (area + it->second.second) / len2(it->second.first, c));
      }
    }
  }
  MassSpringDesc ms;
  ms.nodes.resize(3 * n);
  for (std::size_t i = 0; i < 3 * n; ++i) {
    NodeDesc& nd = ms.nodes[i];
    nd.position = x[i];
    nd.mass = mass[i] > 0 ? mass[i] : 1e-9;
    nd.fixed = i >= 2 * n || (!s.held.empty() && s.held[i % n]);
    nd.damping = desc.damping * nd.mass;
  }
  for (const auto& [ends, k] : springs) {
    // Springs between two bone nodes hold nothing.
    if (ends.first >= static_cast<int>(2 * n) && ends.second >= static_cast<int>(2 * n)) continue;
    ms.springs.push_back({ends.first, ends.second, k, desc.spring_damping * k, -1.0});
    T.stiffness.push_back(k);
    T.rest.push_back(std::sqrt(len2(ends.first, ends.second)));
  }
  indexCorners(T, 3 * n);
  return ms;
}

// Lee, Terzopoulos & Waters 1995, eq. 3: a biphasic spring has stiffness c up to the strain ε_c
// and βc beyond: past ε_c in tension its force is c·ε_c·l + βc·(e − ε_c·l) (in compression the
// mirror). Here the stiffness goes from c to βc over a band of strain ±δ around ε_c (δ = ε_c/3),
// as tissue's stress–strain curve turns (Fung 1993), rather than at a step: the force is the
// paper's outside the band and within (β − 1)c·l·δ/4 of it inside. A step in stiffness made the
// springs near ε_c change phase from one step to the next and back, which the implicit solve's
// warm start could not follow (the face's CG took 9% more iterations). Each step a spring
// takes its tangent stiffness K at its strain now and the rest length that gives the curve's
// force there, K·(L − rest) = F(L), so the implicit integrator sees the phase it is in.
void phaseSprings(const FaceTissue& T, MassSpringModel& m, const std::vector<Vec3>& x) {
  Springs& sp = m.springs;
  const double eps = T.biphasic_strain, beta = T.biphasic_ratio, delta = eps / 3.0;
  parallelFor(static_cast<Index>(sp.size()), [&](Index s) {
    const auto k = static_cast<std::size_t>(s);
    const double l = T.rest[k], c = T.stiffness[k];
    const double len = (x[static_cast<std::size_t>(sp.b[k])] - x[static_cast<std::size_t>(sp.a[k])]).norm();
    const double strain = (len - l) / l, e = std::abs(strain);
    double stiff = c, extra = 0.0;  // tangent stiffness, N/m, and the force beyond c·(L − l), N (for |strain|)
    if (e >= eps + delta || (delta <= 0.0 && e > eps)) {
      stiff = beta * c, extra = (beta - 1) * c * l * (e - eps);
    } else if (e > eps - delta) {
      const double u = e - (eps - delta);  // into the band
      stiff = c + (beta - 1) * c * u / (2 * delta), extra = (beta - 1) * c * l * u * u / (4 * delta);
    }
    sp.stiffness[k] = stiff;
    sp.rest[k] = len - (c * (len - l) + std::copysign(extra, strain)) / stiff;
  });
}

// The volume term of Lee, Terzopoulos & Waters 1995 (eq. 4), as a compliant constraint
// C = V − V₀ with compliance 1/(κ V₀) (Macklin, Müller & Chentanez 2016, "XPBD"): stable at any
// step, and as stiff as κ when the step resolves it. Each element's correction is found alone
// (Jacobi) and each node takes the mean of its elements' corrections. After the implicit solve,
// which holds the volumes itself (TissueVolume), these passes take up what its linearisation
// left.
void preserveVolumes(FaceTissue& T, const MassSpringModel& m, std::vector<Vec3>& x, std::vector<Vec3>& v, double h) {
  if (T.volume_modulus <= 0) return;
  for (int pass = 0; pass < kVolumePasses; ++pass) volumePass(T, m, x, v, h);
}

static void volumePass(FaceTissue& T, const MassSpringModel& m, std::vector<Vec3>& x, std::vector<Vec3>& v, double h) {
  T.corner_vec.resize(6 * T.prisms.size(), Vec3::Zero());
  parallelFor(static_cast<Index>(T.active.size()), [&](Index a) {
    const Index e = T.active[static_cast<std::size_t>(a)];
    const auto& P = T.prisms[static_cast<std::size_t>(e)];
    std::array<Vec3, 6> p;
    for (int c = 0; c < 6; ++c) p[static_cast<std::size_t>(c)] = x[static_cast<std::size_t>(P[static_cast<std::size_t>(c)])];
    std::array<Vec3, 6> grad;
    const double V = prismVolumeGrad(p, &grad);
    const double V0 = T.rest_volume[static_cast<std::size_t>(e)];
    double denom = V0 / (T.volume_modulus * h * h);  // compliance 1/k over h², k = κ/V₀
    for (int c = 0; c < 6; ++c) denom += m.inv_mass[static_cast<std::size_t>(P[static_cast<std::size_t>(c)])] * grad[static_cast<std::size_t>(c)].squaredNorm();
    const double lambda = -(V - V0) / denom;
    for (int c = 0; c < 6; ++c)
      T.corner_vec[static_cast<std::size_t>(6 * e + c)] =
          (lambda * m.inv_mass[static_cast<std::size_t>(P[static_cast<std::size_t>(c)])]) * grad[static_cast<std::size_t>(c)];
  });
  parallelFor(static_cast<Index>(m.nodes()), [&](Index i) {
    const int first = T.corner_start[static_cast<std::size_t>(i)], last = T.corner_start[static_cast<std::size_t>(i) + 1];
    if (m.fixed[static_cast<std::size_t>(i)] || first == last) return;
    Vec3 move = Vec3::Zero();
    for (int q = first; q < last; ++q) move += T.corner_vec[static_cast<std::size_t>(T.corners[static_cast<std::size_t>(q)])];
    move *= kRelaxation / static_cast<double>(last - first);
    x[static_cast<std::size_t>(i)] += move;
    v[static_cast<std::size_t>(i)] += move / h;
  });
}

// Each node's share: Σ over its corners of a[element]·g[corner] (corners in prism order, so the
// same bits at any thread count).
static void gatherScaled(const FaceTissue& T, const std::vector<double>& a, const std::vector<Vec3>& g, Vec3* out) {
  parallelFor(static_cast<Index>(T.corner_start.size() - 1), [&](Index i) {
    const int first = T.corner_start[static_cast<std::size_t>(i)], last = T.corner_start[static_cast<std::size_t>(i) + 1];
    if (first == last) return;
    Vec3 sum = Vec3::Zero();
    for (int q = first; q < last; ++q) {
      const auto k = static_cast<std::size_t>(T.corners[static_cast<std::size_t>(q)]);
      sum += a[k / 6] * g[k];
    }
    out[i] += sum;
  });
}

// Each element's volume gradient at x into g (per corner) and its force's coefficient
// −κ/V₀·(V − V₀) into T.scalar.
static void volumeGradients(FaceTissue& T, const Vec3* x, std::vector<Vec3>& g) {
  g.resize(6 * T.prisms.size(), Vec3::Zero());
  T.scalar.resize(T.prisms.size());
  parallelFor(static_cast<Index>(T.active.size()), [&](Index a) {
    const Index e = T.active[static_cast<std::size_t>(a)];
    const auto& P = T.prisms[static_cast<std::size_t>(e)];
    std::array<Vec3, 6> p, ge;
    for (int c = 0; c < 6; ++c) p[static_cast<std::size_t>(c)] = x[static_cast<std::size_t>(P[static_cast<std::size_t>(c)])];
    const double V = prismVolumeGrad(p, &ge), V0 = T.rest_volume[static_cast<std::size_t>(e)];
    T.scalar[static_cast<std::size_t>(e)] = -T.volume_modulus / V0 * (V - V0);
    for (int c = 0; c < 6; ++c) g[static_cast<std::size_t>(6 * e + c)] = ge[static_cast<std::size_t>(c)];
  });
}

void TissueVolume::addForces(const Vec3* x, Vec3* f) {
  volumeGradients(t_, x, t_.corner_vec);
  gatherScaled(t_, t_.scalar, t_.corner_vec, f);
}

void TissueVolume::linearize(const Vec3* x, Vec3* f, Mat3* diag) {
  FaceTissue& T = t_;
  volumeGradients(T, x, T.grad);
  T.node_grad.resize(T.corners.size());
  parallelFor(static_cast<Index>(T.corner_start.size() - 1), [&](Index i) {
    const int first = T.corner_start[static_cast<std::size_t>(i)], last = T.corner_start[static_cast<std::size_t>(i) + 1];
    for (int q = first; q < last; ++q) {
      const auto k = static_cast<std::size_t>(T.corners[static_cast<std::size_t>(q)]);
      const Vec3& g = T.grad[k];
      diag[i] += (T.volume_modulus / T.rest_volume[k / 6]) * (g * g.transpose());
      T.node_grad[static_cast<std::size_t>(q)] = g;
    }
  });
  // The force: T.scalar holds each element's −κ/V₀·(V − V₀), gathered as a product's is.
  parallelBlocks(static_cast<Index>(T.corner_start.size() - 1), 256, [&](Index i0, Index i1) { addProductTo(i0, i1, f); });
}

void TissueVolume::addProduct(const Vec3* p, double s, Vec3* out) {
  prepareProduct(p, s);
  parallelBlocks(static_cast<Index>(t_.corner_start.size() - 1), 256, [&](Index i0, Index i1) { addProductTo(i0, i1, out); });
}

// Per element: s·κ/V₀·(∇V · p), ∇V at the last linearisation.
void TissueVolume::prepareProduct(const Vec3* p, double s) {
  FaceTissue& T = t_;
  T.scalar.resize(T.prisms.size());
  parallelFor(static_cast<Index>(T.active.size()), [&](Index a) {
    const Index e = T.active[static_cast<std::size_t>(a)];
    const auto& P = T.prisms[static_cast<std::size_t>(e)];
    const Vec3* g = T.grad.data() + 6 * e;
    double dot = 0.0;
    for (int c = 0; c < 6; ++c) dot += g[c].dot(p[static_cast<std::size_t>(P[static_cast<std::size_t>(c)])]);
    T.scalar[static_cast<std::size_t>(e)] = s * T.volume_modulus / T.rest_volume[static_cast<std::size_t>(e)] * dot;
  });
}

// Per node: Σ over its corners, in prism order, of the element's scalar times the corner's ∇V.
void TissueVolume::addProductTo(Index i0, Index i1, Vec3* out) const {
  const FaceTissue& T = t_;
  for (Index i = i0; i < i1; ++i) {
    const int first = T.corner_start[static_cast<std::size_t>(i)], last = T.corner_start[static_cast<std::size_t>(i) + 1];
    Vec3 sum = Vec3::Zero();
    for (int q = first; q < last; ++q)
      sum += T.scalar[static_cast<std::size_t>(T.corner_prism[static_cast<std::size_t>(q)])] * T.node_grad[static_cast<std::size_t>(q)];
    out[i] += sum;
  }
}

// Σ over the elements that hold both a and b of s·κ/V₀·∇_a V ∇_b Vᵀ.
void TissueVolume::addPairBlock(int a, int b, double s, Mat3& out) const {
  const FaceTissue& T = t_;
  for (int q = T.corner_start[static_cast<std::size_t>(a)]; q < T.corner_start[static_cast<std::size_t>(a) + 1]; ++q) {
    const auto e = static_cast<std::size_t>(T.corner_prism[static_cast<std::size_t>(q)]);
    const auto ka = static_cast<std::size_t>(T.corners[static_cast<std::size_t>(q)]);
    for (std::size_t c = 0; c < 6; ++c)
      if (T.prisms[e][c] == b) out += (s * T.volume_modulus / T.rest_volume[e]) * (T.grad[ka] * T.grad[6 * e + c].transpose());
  }
}

double volumeFrequency2(const FaceTissue& T, const MassSpringModel& m, const std::vector<Vec3>& x) {
  std::vector<double> row(m.nodes(), 0.0);
  for (std::size_t e = 0; e < T.prisms.size(); ++e) {
    std::array<Vec3, 6> p, g;
    for (int c = 0; c < 6; ++c) p[static_cast<std::size_t>(c)] = x[static_cast<std::size_t>(T.prisms[e][static_cast<std::size_t>(c)])];
    prismVolumeGrad(p, &g);
    double sum = 0.0;
    for (const Vec3& gc : g) sum += gc.norm();
    for (int c = 0; c < 6; ++c)
      row[static_cast<std::size_t>(T.prisms[e][static_cast<std::size_t>(c)])] += T.volume_modulus / T.rest_volume[e] * g[static_cast<std::size_t>(c)].norm() * sum;
  }
  double w2 = 0.0;
  for (std::size_t i = 0; i < row.size(); ++i)
    if (!m.fixed[i]) w2 = std::max(w2, row[i] * m.inv_mass[i]);
  return w2;
}

double worstVolumeChange(const FaceTissue& T, const std::vector<Vec3>& x) {
  double worst = 0.0;
  for (std::size_t e = 0; e < T.prisms.size(); ++e) {
    std::array<Vec3, 6> p;
    for (int c = 0; c < 6; ++c) p[static_cast<std::size_t>(c)] = x[static_cast<std::size_t>(T.prisms[e][static_cast<std::size_t>(c)])];
    worst = std::max(worst, std::abs(prismVolume(p) - T.rest_volume[e]) / T.rest_volume[e]);
  }
  return worst;
}

}  // namespace reel
