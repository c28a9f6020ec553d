#include "sim/face/face_body.h"

#include <algorithm>
#include <cmath>
#include <span>

#include "core/keys.h"
#include "core/math.h"
#include "core/parallel.h"
#include "sim/contact_layer.h"
#include "sim/grid.h"
#include "sim/stability.h"

namespace reel {

using Index = std::ptrdiff_t;

namespace {

Mat3 aboutX(double a) { return Eigen::AngleAxisd(a, Vec3::UnitX()).toRotationMatrix(); }

}  // namespace

Mat3 FaceBody::jawRotation(double share) const { return R_ * aboutX(share * jaw_); }

Mat3 FaceBody::boneRotation(std::size_t k) const { return jawRotation(surface_.jaw[k]); }

// The mandible opens by turning about the condyles and, as it opens, gliding forward onto the
// articular eminences (about 15 mm over a wide opening; Posselt 1952's envelope of motion): the
// chin goes down more than back, and the floor of the mouth is not crushed against the throat.
Vec3 FaceBody::jawMoved(double share, const Vec3& q) const {
  const Vec3& hinge = surface_.jaw_hinge;
  const double a = share * jaw_;
  return hinge + aboutX(a) * (q - hinge) + Vec3(0, 0, kJawGlide * surface_.scale * a);
}

Vec3 FaceBody::boneToWorld(std::size_t k, const Vec3& q) const { return desc_.position + R_ * jawMoved(surface_.jaw[k], q); }

Vec3 FaceBody::attachmentWorld(std::size_t m) const {
  return desc_.position + R_ * jawMoved(muscles_[m].jaw, muscles_[m].desc.attachment);
}

void FaceBody::pose(double t) {
  t_ = t;
  activations_.at(t, act_);
  // The head: eased between its keys.
  Vec3 deg = desc_.rotation_deg;
  if (!desc_.keys.empty()) {
    const KeySpan k = keySpan(desc_.keys, t, [](const FacePoseKey& key) { return key.time; });
    deg = k.s == 0.0 ? desc_.keys[k.i].rotation_deg
                     : Vec3((1 - easeKey(k.s)) * desc_.keys[k.i].rotation_deg + easeKey(k.s) * desc_.keys[k.i + 1].rotation_deg);
  }
  R_ = rotationFromEulerDeg(deg);
  jaw_ = act_[static_cast<std::size_t>(activations_.index("jaw_open"))] * kJawMaxRad;
  const std::size_t n = surface_.size();
  auto& x = net_.state.x;
  auto& v = net_.state.v;
  for (std::size_t k = 0; k < n; ++k) {
    x[2 * n + k] = boneToWorld(k, surface_.bone[k]);
    v[2 * n + k].setZero();  // fixed nodes carry no velocity (the integrators' rule)
    if (surface_.held.empty() || !surface_.held[k]) continue;
    x[k] = boneToWorld(k, surface_.skin[k]);
    x[n + k] = boneToWorld(k, surface_.skin[k] + fascia_share_ * (surface_.bone[k] - surface_.skin[k]));
    v[k].setZero(), v[n + k].setZero();
  }
}

// Each muscle's pull, shared by the fascia nodes of its zone by their weights (Waters 1987's
// fall-offs, as forces: Lee, Terzopoulos & Waters 1995, section 5), and its bulge: a linear
// muscle's belly thickening as it shortens, as a push off the skull; a sphincter's ring
// thickening, as a push along its axis (defaultMuscles).
void FaceBody::muscleForces() {
  const std::size_t n = surface_.size();
  const auto& x = net_.state.x;
  for (std::size_t m = 0; m < muscles_.size(); ++m) {
    const double a = act_[m];
    if (a <= 0) continue;
    const FaceMuscle& mu = muscles_[m];
    const FaceMuscleDesc& d = mu.desc;
    const Vec3 att = attachmentWorld(m);
    Vec3 u, v;
    sphincterAxes(d.normal.normalized(), u, v);
    const Vec3 center = desc_.position + R_ * d.center;
    const Vec3 uw = R_ * u, vw = R_ * v;
    for (std::size_t j = 0; j < mu.nodes.size(); ++j) {
      const auto k = static_cast<std::size_t>(mu.nodes[j]);
      // Along the skull: its part into the bone is the skull's to bear.
      const Vec3 o = boneRotation(k) * tissue_.out[k];
      Vec3 pull = musclePull(mu, x[n + k], att, center, uw, vw);
      pull -= pull.dot(o) * o;
      ext_[n + k] += (a * d.strength * mu.weight[j]) * pull;
      // And off the skull, where its belly thickens as it shortens, its fibres keeping their
      // volume (Kähler, Haber & Seidel 2001, "Geometry-based muscle modeling for facial animation").
      // A sphincter's ring thickening pushes what it squeezes out along its axis (the lips'
      // pucker pushes them forward off the teeth: pushed off the skull, the upper lip rose and
      // the lower fell, and "oo" bared the teeth).
      if (d.bulge > 0) ext_[n + k] += (d.bulge * a * d.strength * mu.weight[j]) * (d.sphincter ? Vec3(R_ * d.normal.normalized()) : o);
    }
  }
}

void FaceBody::exportContacts(ContactExport& out) const {
  const std::size_t n = surface_.size();
  const bool found = contact_w_.size() == 3 * n && contact_v_.size() == 3 * n;
  out.points(net_.state.x, found ? contact_v_ : net_.state.v, found ? contact_w_ : net_.model.inv_mass, net_.radius);
  const auto& t = surface_.tris;
  for (std::size_t layer : {std::size_t{0}, 2 * n})
    for (std::size_t k = 0; k + 2 < t.size(); k += 3)
      out.triangle(static_cast<int>(layer + t[k]), static_cast<int>(layer + t[k + 1]), static_cast<int>(layer + t[k + 2]));
}

// The skull's non-penetration (Lee, Terzopoulos & Waters 1995, eq. 6, as a constraint on
// position): a node that sinks below its floor above its bone point is put back on it and loses
// its velocity into the skull.
void FaceBody::keepAboveSkull() {
  const std::size_t n = surface_.size();
  auto& x = net_.state.x;
  auto& v = net_.state.v;
  parallelFor(static_cast<Index>(n), [&](Index k) {
    const auto kk = static_cast<std::size_t>(k);
    const Vec3 o = boneRotation(kk) * tissue_.out[kk];
    const Vec3& b = x[2 * n + kk];
    for (std::size_t i : {kk, n + kk}) {
      const double floor = i < n ? tissue_.floor_skin[kk] : tissue_.floor_fascia[kk];
      const double d = (x[i] - b).dot(o);
      if (d >= floor) continue;
      x[i] += (floor - d) * o;
      const double vn = v[i].dot(o);
      if (vn < 0) v[i] -= vn * o;
    }
  });
}

// The scalp is bound to the skull by the galea aponeurotica and moves little over it; the back of
// the neck carries no muscle of the face. Tissue that no muscle's zone and no part of the jaw
// comes within held_beyond of, behind the temples (3 cm in front of the head's centre, scaled
// with the head), is held to the skull: posed with it each step, as the neck's cut end is. Its
// nodes leave the implicit solve, and with them the slowest modes the conjugate gradients had
// to reach (the tissue sliding over the crown and round the neck: docs/face.md, Speed). The
// forehead, which the frontalis lifts, stays free to the crown's front.
void FaceBody::holdScalp(MassSpringDesc& ms) {
  const double reach = desc_.held_beyond;
  if (!(reach > 0)) return;
  const std::size_t n = surface_.size();
  std::vector<Vec3> moved;  // where the muscles pull and the jaw turns (rest skin positions)
  for (const FaceMuscle& m : muscles_)
    for (int k : m.nodes) moved.push_back(surface_.skin[static_cast<std::size_t>(k)]);
  for (std::size_t k = 0; k < n; ++k)
    if (surface_.jaw[k] > 0) moved.push_back(surface_.skin[k]);
  BoxGrid grid;  // the moved points, in cells of the reach: the near ones are in the 27 around
  grid.build(moved, moved, reach);
  const double behind = kHeldFront * surface_.scale, reach2 = reach * reach;
  if (surface_.held.empty()) surface_.held.assign(n, 0);
  parallelFor(static_cast<Index>(n), [&](Index i) {
    const auto k = static_cast<std::size_t>(i);
    if (surface_.held[k] || surface_.skin[k].z() >= behind) return;
    bool near = false;
    grid.forEachNear(surface_.skin[k], [&](std::uint32_t q) { near = near || (moved[q] - surface_.skin[k]).squaredNorm() <= reach2; });
    if (!near) surface_.held[k] = 1;
  });
  for (std::size_t k = 0; k < n; ++k)
    if (surface_.held[k]) ms.nodes[k].fixed = ms.nodes[n + k].fixed = true;
}

void FaceBody::importContacts(std::span<const Vec3> x, std::span<const Vec3> v) {
  SpringNetworkBody::importContacts(x, v);
  // The layer works in the world: back over the skull (less the head's turn it was handed).
  const bool framed = frame_v_.size() == net_.state.v.size();
  for (std::size_t i = 0; i < net_.state.v.size(); ++i)
    if (net_.model.fixed[i]) net_.state.v[i].setZero();
    else if (framed) net_.state.v[i] -= frame_v_[i];
}

void FaceBody::contactState(const std::vector<Vec3>& posed, double h) {
  const std::size_t n = surface_.size();
  const auto& x = net_.state.x;
  // The posed nodes carry no velocity in the state, but they move with the head and the jaw: the
  // layer sees them move (a rope on the crown of a turning head is carried by its friction).
  // The free nodes' state velocities are over the skull (carryWithHead): the layer sees them in
  // the world, with the head's turn over the step added (a turning cheek is moving).
  contact_v_ = net_.state.v;
  frame_v_.assign(x.size(), Vec3::Zero());
  const Vec3 o = desc_.position;
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (!(h > 0)) break;
    if (net_.model.fixed[i]) {
      contact_v_[i] = (x[i] - posed[i]) / h;
    } else {
      frame_v_[i] = (o + step_turn_ * (posed[i] - o) - posed[i]) / h;
      contact_v_[i] += frame_v_[i];
    }
  }
  contact_w_ = net_.model.inv_mass;
  for (std::size_t k = 0; k < n; ++k) {
    const double d = (x[k] - x[2 * n + k]).dot(boneRotation(k) * tissue_.out[k]);
    if (d < tissue_.floor_skin[k] + net_.radius) contact_w_[k] = 0.0;
  }
}

// The tissue is solved in the head's moving frame: each step first carries the free nodes (their
// positions, velocities and the integrator's history) through the head's turn since the last
// step, so the springs and the solve see only the tissue's motion over the skull. Facial tissue
// is bound to the skull by its retaining ligaments (Furnas 1989, "The retaining ligaments of the
// cheek", Plast. Reconstr. Surg. 83(1)) and barely lags a head's turn; solved in the
// world instead, the skin trailed the skull as the head turned (the fixed bone nodes carry no
// velocity, so the springs' damping held it back too): by up to 4 mm at the fastest of the
// film's 70° turn, where the skin sunk under the lids slid out over the eyeball's white.
void FaceBody::carryWithHead(const Mat3& before) {
  const Mat3 turn = R_ * before.transpose();
  step_turn_ = turn;
  if ((turn - Mat3::Identity()).cwiseAbs().maxCoeff() < 1e-15) return;
  const std::size_t n = surface_.size();
  const Vec3 o = desc_.position;
  auto carry = [&](std::vector<Vec3>& x, std::vector<Vec3>* v) {
    for (std::size_t i = 0; i < 2 * n && i < x.size(); ++i) {
      if (net_.model.fixed[i]) continue;  // posed (the held scalp, the neck's cut end)
      x[i] = o + turn * (x[i] - o);
      if (v != nullptr && i < v->size()) (*v)[i] = turn * (*v)[i];
    }
  };
  carry(net_.state.x, &net_.state.v);
  IntegratorWorkspace& ws = net_.workspace;
  if (ws.x_prev.size() == net_.state.x.size()) carry(ws.x_prev, ws.v_prev.size() == ws.x_prev.size() ? &ws.v_prev : nullptr);
  for (std::size_t i = 0; i < 2 * n && i < ws.dv.size(); ++i) ws.dv[i] = turn * ws.dv[i];
}

void FaceBody::step(StepContext& ctx) {
  posed_before_ = net_.state.x;
  const Mat3 before = R_;
  pose(ctx.t1);
  carryWithHead(before);
  ext_.assign(net_.model.nodes(), Vec3::Zero());
  muscleForces();
  phaseSprings(tissue_, net_.model, net_.state.x);
  net_.system->setExternalForces(ext_.data());
  net_.integrate(ctx);
  preserveVolumes(tissue_, net_.model, net_.state.x, net_.state.v, ctx.h);
  keepAboveSkull();
  net_.contacts(ctx);
  contactState(posed_before_, ctx.h);
}

void FaceBody::prepare() {
  ImplicitSettings implicit;
  implicit.cg_tolerance = 1e-6;
  settle(implicit);
}

void FaceBody::settle(const ImplicitSettings& implicit) {
  constexpr double kSettleStep = 0.1;  // s: implicit Euler's large steps, close to a static solve
  // Under gravity from rest, damped by implicit Euler's large steps, then still: a face at rest
  // starts at rest. Settled when no node moves faster than 1 µm/s (after about 20 steps at the
  // default head; the first take most of the solve's iterations) or after 60 steps.
  constexpr double kSettled = 1e-6;  // m/s
  StepStats stats;
  for (int s = 0; s < 60; ++s) {
    net_.system->setExternalForces(nullptr);
    phaseSprings(tissue_, net_.model, net_.state.x);
    integrate(IntegratorKind::ImplicitEuler, *net_.system, net_.state.x, net_.state.v, kSettleStep, net_.workspace, implicit,
              &stats);
    preserveVolumes(tissue_, net_.model, net_.state.x, net_.state.v, kSettleStep);
    keepAboveSkull();
    const auto& v = net_.state.v;
    if (deterministicMax(static_cast<Index>(v.size()), [&](Index i) { return v[static_cast<std::size_t>(i)].norm(); }) < kSettled) break;
  }
  for (Vec3& v : net_.state.v) v.setZero();
  net_.workspace.dv.assign(net_.state.v.size(), Vec3::Zero());
  net_.workspace.forgetHistory();
}

double FaceBody::lowestAboveSkull() const {
  const std::size_t n = surface_.size();
  const auto& x = net_.state.x;
  double low = 1e300;
  for (std::size_t k = 0; k < n; ++k) {
    const Vec3 o = boneRotation(k) * tissue_.out[k];
    for (std::size_t i : {k, n + k}) low = std::min(low, (x[i] - x[2 * n + k]).dot(o));
  }
  return low;
}

double FaceBody::mouthOpening() const {
  if (upper_lip_ == lower_lip_) return 0.0;
  return (net_.state.x[upper_lip_] - net_.state.x[lower_lip_]).norm();
}

bool FaceBody::view(BodyView& out) const {
  SpringNetworkBody::view(out);
  // In the world, as every body's are: the free nodes' velocities over the skull plus the head's
  // turn (contactState), the posed nodes' their motion over the step.
  if (frame_v_.size() == out.velocities.size() && contact_v_.size() == out.velocities.size()) {
    view_v_.resize(out.velocities.size());
    for (std::size_t i = 0; i < view_v_.size(); ++i)
      view_v_[i] = net_.model.fixed[i] ? contact_v_[i] : Vec3(net_.state.v[i] + frame_v_[i]);
    out.velocities = view_v_;
  }
  out.masses = net_.model.mass;
  out.fields.push_back({"muscles", 1, act_});
  return true;
}

void FaceBody::statistics(std::vector<Statistic>& out) const {
  out.push_back({"mouth_opening", mouthOpening()});
  out.push_back({"volume_change", worstVolumeChange(tissue_, net_.state.x)});
  double sum = 0.0;
  for (std::size_t m = 0; m < muscles_.size(); ++m) sum += act_[m];
  out.push_back({"mean_contraction", muscles_.empty() ? 0.0 : sum / static_cast<double>(muscles_.size())});
}

std::vector<std::string> FaceBody::notes(double) const {
  std::string names;
  for (const std::string& c : activations_.controls) names += (names.empty() ? "" : ", ") + c;
  return {std::to_string(2 * surface_.size()) + " tissue nodes over " + std::to_string(surface_.size()) + " skull points, " +
              std::to_string(net_.model.springs.size()) + " springs, " + std::to_string(tissue_.prisms.size()) + " elements",
          "controls (the dump's `muscles`, in this order): " + names};
}

void FaceBody::snapshotMore(StateWriter& w) const {
  w.put(t_);
}

bool FaceBody::restoreMore(StateReader& r) {
  double t = 0;
  r.get(t);
  if (!std::isfinite(t)) return false;
  pose(t);
  return true;
}

Status FaceBody::setup(const BodyDesc& desc, const BuildContext& ctx) {
  const std::string& file = ctx.scene->file;
  const double thickness = desc_.dermis.thickness + desc_.muscle.thickness;
  if (desc_.mesh) {
    auto s = userHead(*desc_.mesh, desc_.skull.get(), desc_.inset, file + ": " + desc.path + "/mesh");
    if (!s) return s.error();
    surface_ = std::move(s.value());
  } else {
    surface_ = makeHead(desc_.height, desc_.resolution, thickness, desc_.look);
  }
  MassSpringDesc ms = buildTissue(surface_, desc_, tissue_);
  // Muscles: reel's head's own, then the scene's.
  std::vector<FaceMuscleDesc> all;
  if (surface_.generated && desc_.default_muscles) all = defaultMuscles(surface_);
  for (const FaceMuscleDesc& m : desc_.muscles) all.push_back(m);
  std::vector<Vec3> fascia(surface_.size());
  for (std::size_t k = 0; k < surface_.size(); ++k) fascia[k] = ms.nodes[surface_.size() + k].position;
  for (const FaceMuscleDesc& m : all) {
    auto placed = placeMuscle(m, surface_, fascia, file);
    if (!placed) return placed.error();
    muscles_.push_back(std::move(placed.value()));
  }
  if (surface_.generated) holdScalp(ms);
  keepActive(tissue_, ms);
  fascia_share_ = desc_.dermis.thickness / (desc_.dermis.thickness + desc_.muscle.thickness);
  MassSpringDesc scaled = ms;
  const Vec3 gravity = desc_.gravity_scale * ctx.scene->gravity;
  // Place the head: nodes in the world.
  const Mat3 R = rotationFromEulerDeg(desc_.keys.empty() ? desc_.rotation_deg : desc_.keys.front().rotation_deg);
  for (NodeDesc& nd : scaled.nodes) nd.position = desc_.position + R * nd.position;
  net_.build(scaled, gravity, ctx.scene->integrator, 0.002);
  net_.system->setForceTerm(&volume_);
  // Each vertex's skin and fascia nodes, a few millimetres of tissue apart, preconditioned
  // together (their springs and shared elements couple them far more than their neighbours do):
  // the conjugate gradients take fewer iterations.
  {
    const std::size_t n = surface_.size();
    std::vector<std::array<int, 2>> pairs;
    for (std::size_t k = 0; k < n; ++k)
      if (!net_.model.fixed[k] && !net_.model.fixed[n + k]) pairs.push_back({static_cast<int>(k), static_cast<int>(n + k)});
    net_.system->setPreconditionerPairs(std::move(pairs));
  }
  // An explicit method's bound: with every spring in its stiff phase.
  for (double& k : net_.model.springs.stiffness) k *= desc_.biphasic_ratio;
  net_.bound = stableStep(net_.model, ctx.scene->integrator);
  net_.model.springs.stiffness = tissue_.stiffness;
  // ... and the volume term's stiffness on top of the springs' (both bounds by Gershgorin).
  if (net_.bound.h_max > 0 && std::isfinite(net_.bound.h_max)) {
    const double w2 = net_.bound.omega * net_.bound.omega + volumeFrequency2(tissue_, net_.model, net_.state.x);
    net_.bound.omega = std::sqrt(w2);
    net_.bound.h_max = oscillatorBound(ctx.scene->integrator, w2, net_.bound.beta);
  }
  if (std::string e = net_.unstableMethod(desc.name, ctx.scene->integrator); !e.empty())
    return Error(ErrorKind::BadInput, file + ": " + e);
  auto acts = makeActivations(desc_, muscles_, file);
  if (!acts) return acts.error();
  activations_ = std::move(acts.value());
  // The lips' parting at the midline: the mouth vertex and its lower copy.
  if (surface_.generated)
    for (std::size_t k = 0; k < surface_.size(); ++k) {
      if ((surface_.skin[k] - surface_.mouth).squaredNorm() > 1e-14) continue;
      (upper_lip_ == 0 ? upper_lip_ : lower_lip_) = k;
    }
  if (lower_lip_ == 0) lower_lip_ = upper_lip_;
  pose(0.0);
  return {};
}

Result<std::unique_ptr<Body>> buildFaceBody(const BodyDesc& desc, const BuildContext& ctx) {
  Material material = desc.material;
  auto body = std::make_unique<FaceBody>(desc.name, desc.as<FaceDesc>(), material);
  if (Status st = body->setup(desc, ctx); !st) return st.error();
  return std::unique_ptr<Body>(std::move(body));
}

}  // namespace reel
