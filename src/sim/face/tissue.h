// The face's tissue (Lee, Terzopoulos & Waters 1995, section 4): three surfaces of nodes, the
// epidermis on the skin, the fascia below the dermal–fatty layer, the bone on the skull; each
// surface triangle makes a prism element in each of the two layers. Springs join the nodes
// within the epidermis and the fascia, and across each layer (straight down and crosswise).
// The tissue's springs are biphasic (stiffer past a strain); each element keeps its volume; the
// face body keeps the nodes above the skull.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "core/scene/face.h"
#include "core/scene/mass_spring.h"
#include "core/types.h"
#include "sim/face/head.h"
#include "sim/mass_spring.h"

namespace reel {

struct FaceTissue {
  std::size_t n = 0;  // surface vertices: node k is its epidermis, n + k its fascia, 2n + k its bone
  // Elements: prisms, the lower triangle's three nodes then the upper's (same order).
  std::vector<std::array<int, 6>> prisms;
  std::vector<double> rest_volume;  // m³ (prisms)
  double volume_modulus = 0.0;      // Pa
  // For each node, its (prism, corner) pairs in prism order (compressed rows): the volume forces
  // gathered in a fixed order. corners holds 6·prism + corner, corner_prism the prism alone.
  std::vector<int> corner_start, corners, corner_prism;
  // The prisms with a free node, the only ones the volume term evaluates (a prism of fixed nodes
  // keeps its volume; its scalar and gradients stay 0, read only by fixed nodes' rows).
  std::vector<int> active;
  double biphasic_strain = 0.0, biphasic_ratio = 1.0;
  std::vector<double> stiffness, rest;  // the springs' own (first phase), N/m and m
  // The skull: each vertex's outward direction in the head frame (bone → skin at rest) and the
  // least height above its bone point its fascia and epidermis nodes keep, m.
  std::vector<Vec3> out;
  std::vector<double> floor_fascia, floor_skin;
  // Scratch: per element, a scalar of the last product; per corner, the volume gradient at the
  // last linearisation (again in each node's order, node_grad, for the products' gathers to read
  // in sequence) and a vector to gather. (Rounded to single precision, as the springs' blocks
  // are, the gradients cost the face's CG 17% more iterations at the film's tolerance.)
  std::vector<double> scalar;
  std::vector<Vec3> grad, node_grad, corner_vec;
};

// The elements' resistance to a change of volume as an energy (Lee, Terzopoulos & Waters 1995,
// eq. 4, with k = κ/V₀): E = Σ κ/(2V₀)·(V − V₀)², its force −κ/V₀·(V − V₀)·∇V, taken inside the
// implicit solve by its Gauss–Newton stiffness κ/V₀·∇V ∇Vᵀ, so the muscles' pull and the tissue's
// volume are balanced in one solve rather than by projections after it.
class TissueVolume final : public ForceTerm {
 public:
  explicit TissueVolume(FaceTissue& t) : t_(t) {}
  void addForces(const Vec3* x, Vec3* f) override;
  void linearize(const Vec3* x, Vec3* f, Mat3* diag) override;
  void addProduct(const Vec3* p, double s, Vec3* out) override;
  void prepareProduct(const Vec3* p, double s) override;
  void addProductTo(std::ptrdiff_t i0, std::ptrdiff_t i1, Vec3* out) const override;
  void addPairBlock(int a, int b, double s, Mat3& out) const override;

 private:
  FaceTissue& t_;
};

// Nodes and springs of the tissue over `surface` (bone nodes fixed), and the tissue's own terms.
MassSpringDesc buildTissue(const FaceSurface& surface, const FaceDesc& desc, FaceTissue& tissue);

// Each node's corners (corner_start, corners, corner_prism) from the prisms, over `nodes` nodes;
// every prism active.
void indexCorners(FaceTissue& tissue, std::size_t nodes);

// Only the prisms with a node that `ms` leaves free active. (The springs between fixed nodes stay:
// the layers' lattice draws them, and they cost only their share of the step's linearisation.)
void keepActive(FaceTissue& tissue, const MassSpringDesc& ms);

// The signed volume of a prism (its boundary, each side quad the mean of its two splits), m³.
double prismVolume(const std::array<Vec3, 6>& p);

// Sets each spring's phase from its strain now (biphasic springs, as stiffness and rest length of
// the model's springs, so the integrator, implicit Euler too, sees the phase it is in).
void phaseSprings(const FaceTissue& tissue, MassSpringModel& model, const std::vector<Vec3>& x);

// Moves the nodes toward each element's rest volume (Jacobi passes of compliant constraints),
// and their velocities with them; step h.
void preserveVolumes(FaceTissue& tissue, const MassSpringModel& model, std::vector<Vec3>& x, std::vector<Vec3>& v, double h);

// The highest angular frequency² (rad²/s²) the volume term gives a free node at the positions x
// (the Gershgorin bound of M⁻¹H, as the springs' step bound takes it).
double volumeFrequency2(const FaceTissue& tissue, const MassSpringModel& model, const std::vector<Vec3>& x);

// The largest relative change of volume of any element, for checks and statistics.
double worstVolumeChange(const FaceTissue& tissue, const std::vector<Vec3>& x);

}  // namespace reel
