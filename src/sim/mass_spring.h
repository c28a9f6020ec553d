// The mass-spring-damper model (DESIGN 1): nodes with mass and nodal drag, Voigt springs,
// fixed nodes, gravity. Model (what the body is) and state (where it is) are kept apart
// (MuJoCo's mjModel/mjData): every integrator reads the model and advances the state.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "core/scene.h"
#include "core/scene/mass_spring.h"
#include "core/types.h"
#include "sim/integrators.h"
#include "sim/skyline.h"

namespace reel {

// Springs as parallel arrays (springs); referred to by index.
struct Springs {
  std::vector<int> a, b;             // end nodes
  std::vector<double> stiffness;     // c, N/m
  std::vector<double> damping;       // γ_s, N·s/m
  std::vector<double> rest;          // l, m
  std::size_t size() const { return a.size(); }
  void add(int na, int nb, double c, double g, double l) {
    a.push_back(na); b.push_back(nb); stiffness.push_back(c); damping.push_back(g); rest.push_back(l);
  }
};

// For each node, the springs that touch it, in a fixed order (compressed rows). An entry is
// 2·s for a spring whose end a is the node and 2·s + 1 for end b. Gathering per-spring values
// through it sums each node's forces in one fixed order: deterministic for any thread count,
// with no atomics.
struct Incidence {
  std::vector<int> start;    // (nodes + 1)
  std::vector<int> entries;  // (2 · springs)
  std::vector<int> other;    // the node at the spring's other end, per entry (2 · springs)
  std::uint64_t generation = 0;  // a number no other build() gave (a changed network is a new one)
  void build(std::size_t nodes, const Springs& s);
};

struct MassSpringModel {
  std::vector<double> mass;      // kg (nodes)
  std::vector<double> inv_mass;  // 1/kg, 0 for fixed nodes (nodes)
  std::vector<double> drag;      // nodal γ_i, N·s/m (nodes)
  std::vector<std::uint8_t> fixed;  // 1 for a fixed node (nodes)
  Springs springs;
  Incidence incidence;
  Vec3 gravity{0, -9.78, 0};  // m/s²
  std::size_t nodes() const { return mass.size(); }
};

// Sets node i's mass (a cloth soaking up liquid); a fixed node keeps inverse mass 0.
inline void setNodeMass(MassSpringModel& m, std::size_t i, double mass) {
  m.mass[i] = mass;
  m.inv_mass[i] = m.fixed[i] ? 0.0 : 1.0 / mass;
}

struct MassSpringState {
  std::vector<Vec3> x;  // positions, m (nodes)
  std::vector<Vec3> v;  // velocities, m/s (nodes)
};

// Builds model and state from explicit nodes and springs (already validated).
void buildMassSpring(const MassSpringDesc& desc, const Vec3& gravity, MassSpringModel& model,
                     MassSpringState& state);

// A force term beyond the springs and drags (a tissue's resistance to a change of volume), which
// the implicit integrators take inside their solve by a stiffness H ≈ −∂f/∂x, symmetric positive
// semi-definite (a Gauss–Newton stiffness serves). Forces on fixed nodes are ignored.
class ForceTerm {
 public:
  virtual ~ForceTerm() = default;
  // Adds the term's force at x to f, N per node.
  virtual void addForces(const Vec3* x, Vec3* f) = 0;
  // Linearises at x (what products need): adds the term's force at x to f, as addForces does,
  // and each node's diagonal block of H to diag.
  virtual void linearize(const Vec3* x, Vec3* f, Mat3* diag) = 0;
  // out += s·H p, H from the last linearize().
  virtual void addProduct(const Vec3* p, double s, Vec3* out) = 0;
  // The same product in two halves, so that a system can take the second inside its own pass
  // over the nodes: prepareProduct(p, s) once, then addProductTo(i0, i1, out) adds s·H p to
  // out's nodes [i0, i1) (any ranges that cover the nodes, in any order).
  virtual void prepareProduct(const Vec3* p, double s) = 0;
  virtual void addProductTo(std::ptrdiff_t i0, std::ptrdiff_t i1, Vec3* out) const = 0;
  // out += s·H_ab, the block of H from the last linearize() that couples node a's force to node
  // b's displacement (for a preconditioner that inverts a and b together); none by default.
  virtual void addPairBlock(int /*a*/, int /*b*/, double /*s*/, Mat3& /*out*/) const {}
};

// The model as an OdeSystem (x'' = a(x, v)) for the integrators: accelerations, and the linearised system of
// implicit Euler. Holds scratch arrays, so one instance per body and thread of control.
class MassSpringSystem final : public OdeSystem {
 public:
  // The springs at one node, four at a time, for the conjugate-gradient products: their blocks
  // in single precision (half the memory traffic; both ends of a spring read the same rounded
  // block, so the system stays symmetric), lane k holding spring k, and the nodes at their other
  // ends. A node's last group is padded with zero blocks that point back at the node. The
  // rounding, under 6·10⁻⁸ of a block, is far below the tolerances used in practice (10⁻²–10⁻⁴);
  // the system solved is the rounded one, so a tolerance below about 10⁻⁷ tightens the solve of
  // that system, not its agreement with the exact matrix.
  struct alignas(16) Group4 {
    float b[6][4];  // xx, yy, zz, xy, xz, yz
    int other[4];
  };
  explicit MassSpringSystem(const MassSpringModel& m) : m_(m) {}
  std::size_t size() const override { return m_.nodes(); }
  bool fixed(std::size_t i) const override { return m_.fixed[i] != 0; }
  void acceleration(const Vec3* x, const Vec3* v, Vec3* a) override;
  bool linearizable() const override { return true; }
  void linearize(const Vec3* x, const Vec3* v, const Vec3* w, double h, Vec3* rhs, Mat3* block_inverse) override;
  double mass(std::size_t i) const override { return m_.mass[i]; }
  void applySystem(const Vec3* p, Vec3* out) override;
  // Forces from outside the spring network (air on a cloth), N per node, held over a step;
  // nullptr for none. The array must outlive the steps that use it.
  void setExternalForces(const Vec3* f) { external_ = f; }
  // A linear drag toward a flow at each node, f_i = D_i u_i − D_i v_i (D_i symmetric positive
  // semi-definite, kg/s; `Du` holds D_i u_i), held over a step: the implicit integrators take it
  // inside their solve (A gains h D_i), so a stiff drag on a light node is neither split from the springs
  // nor limited by the step. nullptr for none; the arrays must outlive the steps that use them.
  void setNodeDrag(const Mat3* D, const Vec3* Du) { node_drag_ = D, node_flow_ = Du; }
  // A force term of its own (ForceTerm), taken in every evaluation and inside the implicit
  // solve; nullptr for none. It must outlive the steps that use it.
  void setForceTerm(ForceTerm* t) { term_ = t; }
  // The implicit integrators' right-hand side takes a spring's force at the step's end as Baraff
  // & Witkin linearise it, f₀ + h K v. For a compressed spring K drops the transverse term (it
  // would be negative), so the extrapolation misses how the push of a compressed spring turns as
  // the spring turns: an error of O(h²) a step, whatever the integrator. A swimming fish, whose
  // compressed flank springs turn fast, swam 2.3 m in 5 s at 6 substeps and 3.3 m at 20. With
  // the predictor on, a compressed spring's force is taken at the predicted positions x + h v
  // (K then only multiplies the correction h Δv) and the fish swims the same distance within 3%
  // from 6 substeps up, with implicit Euler or BDF2. Off by default: taken for stretched springs
  // too it let fast light nodes run away, and sheets and the face, stepped far beyond the
  // explicit bound, keep the plain extrapolation.
  void setPredictor(bool on) { predict_ = on; }
  // Pairs of free nodes {a, b}, each node in one pair at most, whose 6×6 block of A the
  // preconditioner inverts together (OdeSystem::preconditionerPairs); empty for none.
  void setPreconditionerPairs(std::vector<std::array<int, 2>> pairs);
  PreconditionerPairs preconditionerPairs() const override;
  // Each piece of the network (its free nodes joined by springs: a fish, a rope) factorised by
  // Cholesky in envelope storage (sim/skyline.h), with the springs' blocks in double precision;
  // not with a force term (its blocks between nodes are not listed), nor where the largest
  // piece's factor would pass kDirectMaxDoubles.
  void setLinearSolver(LinearSolver s) override { solver_ = s; }
  bool solveDirect(const Vec3* rhs, Vec3* dv) override;
  static constexpr std::size_t kDirectMaxDoubles = std::size_t{1} << 24;  // 128 MiB a thread
  static constexpr std::size_t kDirectKeepDoubles = std::size_t{1} << 17;  // a thread keeps 1 MiB of scratch
  // Spring force evaluations done so far (for benchmarks).
  std::uint64_t springEvaluations() const { return spring_evals_; }
  // Products with a spring's 3×3 block in implicit Euler's conjugate-gradient solve.
  std::uint64_t springProducts() const { return spring_products_; }

 private:
  // out_i = Σ over springs at i of ±per_spring[s] (+ on end a, − on end b).
  void gather(const std::vector<Vec3>& per_spring, std::size_t i, Vec3& out) const;
  bool planDirect();
  void sizeCg();
  void cgNode(std::ptrdiff_t i);
  void cgPairs();
  void ensureCg();
  const MassSpringModel& m_;
  std::vector<Vec3> fs_;  // per-spring force on end a, N (springs)
  // A symmetric 3×3 block: xx, yy, zz, xy, xz, yz.
  struct Sym3 {
    double m[6];
  };
  std::vector<Sym3> B_;            // per-spring h²K + hD (springs), valid after linearize()
  std::vector<Group4> groups_;     // node by node
  std::vector<int> group_start_;   // (nodes + 1)
  std::vector<double> own_;        // m + hγ per node
  std::vector<std::ptrdiff_t> free_end_;     // for a free node, where its run of free nodes ends
  std::vector<std::ptrdiff_t> piece_start_;  // the products' pieces of about equal work (pieces + 1)
  std::vector<std::array<int, 2>> pairs_;    // the preconditioner's pairs
  std::vector<int> partner_;                 // per node, its pair's other node (−1: none) after linearize()
  std::vector<Eigen::Matrix<double, 3, 6>> pair_rows_;  // per paired node, its rows of the pair block's inverse
  std::vector<Mat3> diag_;                   // per paired node, its diagonal block of A
  const Vec3* external_ = nullptr;
  const Mat3* node_drag_ = nullptr;
  const Vec3* node_flow_ = nullptr;
  ForceTerm* term_ = nullptr;
  std::vector<Vec3> term_f_;   // the term's force at the linearisation, and (implicit) − h H w
  std::vector<Mat3> term_d_;   // its diagonal blocks
  double h_ = 0.0;  // the step of the last linearize()
  LinearSolver solver_ = LinearSolver::Auto;
  bool direct_ = false;                     // the last linearize() prepared a direct solve (no CG arrays)
  Mat3* block_inverse_ = nullptr;           // the preconditioner's blocks the last linearize() was given
  SkylinePlan plan_;                        // the pieces, for the direct solve
  std::uint64_t plan_generation_ = 0;       // the incidence it was made from
  std::vector<std::uint8_t> plan_fixed_;    // and the fixed nodes
  std::vector<int> piece_spring_start_;     // (pieces + 1) into piece_springs_
  std::vector<int> piece_springs_;          // per piece, the springs with a free end in it, in index order
  std::vector<std::uint8_t> failed_;        // per piece: its factorisation failed (this step)
  bool predict_ = false;
  std::uint64_t spring_evals_ = 0;
  std::uint64_t spring_products_ = 0;
  std::uint64_t products_per_apply_ = 0;  // spring blocks one product with A takes (free rows)
};

// Total energy (kinetic + spring potential − m g·x), J; used by tests and benches.
double kineticEnergy(const MassSpringModel& m, const MassSpringState& s);
double totalEnergy(const MassSpringModel& m, const MassSpringState& s);

}  // namespace reel
