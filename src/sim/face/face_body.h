// The face kind: the tissue (tissue.h) on the shared spring network, over a skull that the head's
// pose keys turn and whose jaw opens, moved by Waters' muscles (muscles.h) as activation keys
// and presets say. Drawn as skin with eyes, eyelids and a mouth, or as its layers and muscles
// (face_draw.cpp).
#pragma once

#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "core/scene/face.h"
#include "sim/face/head.h"
#include "sim/face/head_shape.h"
#include "sim/face/muscles.h"
#include "sim/face/tissue.h"
#include "sim/spring_network.h"

namespace reel {

class FaceBody final : public SpringNetworkBody {
 public:
  FaceBody(std::string name, const FaceDesc& desc, const Material& material)
      : SpringNetworkBody(std::move(name), "face"), desc_(desc), material_(material) {}
  void step(StepContext& ctx) override;
  void draw(DrawList& out) const override;
  bool view(BodyView& out) const override;
  void statistics(std::vector<Statistic>& out) const override;
  std::vector<std::string> notes(double h) const override;
  // It meets every other body through the World's contact layer with all its nodes and two
  // surfaces over them: the skin (the epidermis nodes' triangles) and the skull (the same
  // triangles over the bone nodes, held). The skin is light: a hard hit dents it into the tissue,
  // and the skull under it stops what the skin did not. A skin node pressed down to its floor above
  // the bone rests on the skull, which no contact moves: the layer sees it held.
  bool exportsContacts() const override { return true; }
  void exportContacts(ContactExport& out) const override;
  // The layer's velocities back, the posed nodes' left at rest (the integrators' rule).
  void importContacts(std::span<const Vec3> x, std::span<const Vec3> v) override;

  const FaceSurface& surface() const { return surface_; }
  const FaceTissue& tissue() const { return tissue_; }
  const std::vector<FaceMuscle>& muscles() const { return muscles_; }
  const FaceActivations& activations() const { return activations_; }
  const std::vector<double>& contractions() const { return act_; }
  // The head's rotation and the jaw's opening angle (rad) at the last pose.
  const Mat3& rotation() const { return R_; }
  double jawAngle() const { return jaw_; }
  // An eye of reel's head now (0: left, +x; 1: right): its centre and axes in the world (the
  // gaze's right, up and ahead), its radius, and its lids: a shell of `lid_radius` about the
  // centre spanning ±`lid_azimuth` around the head's forward axis (azimuth az, rad, toward the
  // head's +x), the upper lid above the elevation upperEdge(az) and the lower below
  // lowerEdge(az) (rad, in the head's frame; a shut eye has upper < lower). The lids' margins
  // curve, an almond: each meets the other at the corners (`corner` rad from the middle; the
  // outer corner `tilt` rad higher than the inner, the canthal tilt), the upper highest just
  // inside the middle at `upper`, the lower lowest just outside it at `lower`.
  struct Eye {
    Vec3 center{0, 0, 0}, right{1, 0, 0}, up{0, 1, 0}, ahead{0, 0, 1};
    double radius = 0.0, lid_radius = 0.0, lid_azimuth = 0.0, upper = 0.0, lower = 0.0;
    double corner = 0.0, tilt = 0.0, corners = 0.0;  // corners: the corners' mean elevation, rad (eye(): head::kEyeCorner...)
    double outward = 1.0;  // +1 where the outer corner lies toward +x (the left eye), -1 else
    double closure = 0.0;  // 0 open .. 1 shut: the upper margin brought down past the lower
    double upperEdge(double az) const;
    double lowerEdge(double az) const;
  };
  Eye eye(int e) const;
  // The albedo the mouth's inside is drawn with (its vertex colours shade it, red at the lips'
  // inner faces, near black past them); tests find its mesh by it.
  static inline const Vec3 kMouthInside{1.0, 0.999, 0.998};
  // The lips' rims' colour at their outer ends (addLipRims; 0.3 of it at their inner ends):
  // tests find the rims by it.
  static inline const Vec3 kLipRim{0.36, 0.1, 0.09};
  // The head-frame point q moved by the jaw now, taking `share` (0..1) of its motion.
  Vec3 jawMoved(double share, const Vec3& q) const;
  // The skin as drawn: reel's head finer than it is simulated (SkinDetail, with its texture
  // coordinates and per-vertex wrinkle weights, wrinkleDepth's; `relaxed`, when given,
  // receives the simulated skin's points the fine skin was placed over), a user's mesh as it is.
  // `lost`, when given, receives each drawn vertex's share of area lost from rest.
  // `lines`, when given, receives their wrinkleDepth.
  std::shared_ptr<TriMesh> skinMesh(std::vector<Vec3>* relaxed = nullptr, std::vector<double>* lost = nullptr,
                                    std::vector<double>* lines = nullptr) const;
  // How deep the wrinkle map sinks at each vertex of the skin drawn (skinMesh) now (0..1):
  // in each region as the muscle that makes it pulls, or as far as the skin there has shrunk
  // (`lost`, skinMesh's, one per vertex drawn); reel's head only (empty for a user's mesh).
  std::vector<double> wrinkleDepth(const std::vector<double>& lost) const;
  // The height of each moving node above its skull point (m; negative: through the skull).
  double lowestAboveSkull() const;
  // Mouth opening: the distance between the lips at the midline, m (0 without a mouth).
  double mouthOpening() const;

  // Builds everything but the network; the builder then settles the face under gravity.
  Status setup(const BodyDesc& desc, const BuildContext& ctx);
  void prepare() override;  // settles under gravity (settle)
  void settle(const ImplicitSettings& implicit);

 protected:
  void snapshotMore(StateWriter& w) const override;
  bool restoreMore(StateReader& r) override;

 private:
  // Poses the skull at time t: the activations, the head's rotation, the jaw, the bone nodes.
  void pose(double t);
  // Carries the free tissue through the head's turn from `before` to now (step).
  void carryWithHead(const Mat3& before);
  // The skull's frame at bone vertex k: where the head frame's point q under it goes (world).
  Vec3 boneToWorld(std::size_t k, const Vec3& q) const;
  Mat3 boneRotation(std::size_t k) const;
  // The head's turn now with `share` (0..1) of the jaw's: what jawMoved does to directions.
  Mat3 jawRotation(double share) const;
  // Muscle m's attachment in the world (on the jaw, it moves with it).
  Vec3 attachmentWorld(std::size_t m) const;
  void muscleForces();
  void keepAboveSkull();
  // Holds the tissue far from every muscle and the jaw to the skull (desc_.held_beyond): marks
  // surface_.held and fixes the nodes in `ms`.
  void holdScalp(MassSpringDesc& ms);
  // Each node's inverse mass and velocity as the contact layer sees them (a skin node resting on
  // the skull: mass 0; a posed node, the bone and the held tissue: its motion over the step, from
  // `posed`, its positions before the step's pose).
  void contactState(const std::vector<Vec3>& posed, double h);
  // The skin and what goes with it (ears, hair, shoulders, eyes, lids and lashes, the mouth's
  // cavity, teeth and tongue).
  void drawSkin(DrawList& out) const;
  void drawEyes(DrawList& out) const;
  // The teeth, both rows, their shade times `lit` (0..1: little light reaches into a closed mouth).
  void drawTeeth(DrawList& out, double lit) const;
  // How much light reaches into the mouth as open as it is now: `closed` shut, rising from `from`
  // open (m at a head 0.24 m high) to 1 over `over` more. By default the teeth's and the tongue's
  // shade in the skin's view (0.15 closed, 1 from 8 mm open).
  double mouthLight(double closed = 0.15, double from = 0.002, double over = 0.006) const;
  // The shoulders in their sweater (reel's head, `shoulders`), in every mode.
  void drawBust(DrawList& out) const;
  // The lips' thickness where they part, added to the mouth's lining `inside` (drawSkin).
  void addLipRims(TriMesh& inside, const std::vector<Vec3>& relaxed) const;
  // The brows' hairs, each on a point of the skin drawn (`skin`, drawSkin's), added to the hair's
  // strands (face_brows.cpp); where they root and how they lie, made once.
  struct BrowHair {
    std::uint32_t vertex = 0;         // the point of the skin drawn it roots at
    Vec3 offset{0, 0, 0};             // from that point, m in the head's x-y plane (laid on the skin's plane when drawn)
    Vec3 direction{0, 1, 0};          // how it lies, in the head's frame at rest (unit)
    double length = 0.0, lift = 0.0;  // m; its tip's rise off the skin, a share of its length
    float shade = 1.0f;
  };
  void addBrowHairs(TriMesh& strands, const TriMesh& skin) const;
  const std::vector<BrowHair>& browHairs() const;
  // reel's head's finer skin (with its points at rest and their wrinkles' regions), made once.
  const SkinDetail& detail() const;
  // The layers and muscles cut away over the skull; `reveal` (0..1) how far a dissolve from or to
  // the skin has gone: what lies at the skin or outside it grows in with it (the lattice's layers
  // rise to their places from the bone, the sphincters' bands widen) and the teeth come out
  // of the mouth's dark, so the skin over them at nearly full opacity hides them (all at once,
  // they popped through it in one frame).
  void drawLayers(DrawList& out, double reveal = 1.0) const;
  // The layers' frontalis, one sheet over the forehead; onSkull lays a world point on the skull
  // drawn (and gives its normal there).
  void drawFrontalis(DrawList& out, const std::function<Vec3(const Vec3&, Vec3*)>& onSkull) const;
  // The layers' skull: the bone layer sculpted as a skull, its points at rest in the head frame
  // and their shades (made once, face_layers.cpp).
  void sculptSkull() const;

  FaceDesc desc_;
  Material material_;
  FaceSurface surface_;
  FaceTissue tissue_;
  TissueVolume volume_{tissue_};
  std::vector<FaceMuscle> muscles_;
  FaceActivations activations_;
  std::vector<double> act_;  // contractions now (controls)
  std::vector<Vec3> ext_;    // muscle and tissue forces, N (nodes)
  std::vector<double> contact_w_;  // 1/kg (nodes) as the contact layer sees them, found at the end of each step
  std::vector<Vec3> contact_v_;    // m/s (nodes), likewise
  // m/s (nodes): what the head's turn over the last step moved each free node at, which the
  // state's velocities (over the skull, carryWithHead) leave out; zero on posed nodes.
  std::vector<Vec3> frame_v_;
  Mat3 step_turn_ = Mat3::Identity();  // the head's turn over the last step (carryWithHead)
  mutable std::vector<Vec3> view_v_;   // the nodes' world velocities, for view()
  std::vector<Vec3> posed_before_;  // the nodes' positions at the start of the step (scratch)
  // reel's head's skin, made once when first drawn (drawing is const; the flag makes it once).
  mutable std::once_flag skin_once_;
  mutable std::shared_ptr<const Image> skin_texture_, skin_relief_, skin_wrinkles_;
  mutable std::once_flag detail_once_;
  mutable std::once_flag skull_once_;
  mutable std::vector<Vec3> skull_rest_;
  mutable std::vector<float> skull_shade_;
  mutable SkinDetail detail_;
  mutable std::vector<Vec3> detail_rest_;  // its points at rest, in the head's frame
  mutable std::vector<head::Wrinkles> detail_regions_;  // their wrinkles' regions (head::wrinkleRegions)
  mutable std::once_flag brows_once_;
  mutable std::vector<BrowHair> brows_;
  double t_ = 0.0;           // time of the last pose, s
  Mat3 R_ = Mat3::Identity();
  double jaw_ = 0.0;
  double fascia_share_ = 0.5;  // the fascia's share of the way from the skin to the bone
  std::size_t upper_lip_ = 0, lower_lip_ = 0;  // midline vertices of the lips' parting
};

Result<std::unique_ptr<Body>> buildFaceBody(const BodyDesc& desc, const BuildContext& ctx);

// The largest jaw opening, at jaw_open = 1, rad.
inline constexpr double kJawMaxRad = 0.3;
// How far the jaw glides forward as it opens, m per rad at a head 0.24 m high.
inline constexpr double kJawGlide = 0.05;
// Held tissue lies behind this plane, m in front of the head's centre at a head 0.24 m high (the
// temples): the scalp in front of it follows the frontalis.
inline constexpr double kHeldFront = 0.03;

}  // namespace reel
