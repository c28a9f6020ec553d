// The fish kind: one or many artificial fish of one species as a body. All its fish share one
// spring network (23 nodes and 91 units each, fish after fish), stepped by the scene's integrator;
// the water's forces are taken implicitly node by node after it; perception and behaviour decide
// ten times a second. Drawn as skinned bodies or as the wireframe model (fish_draw.cpp).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "core/image.h"
#include "core/scene/fish.h"
#include "sim/fish/behaviour.h"
#include "sim/fish/fish.h"
#include "sim/spring_network.h"

namespace reel {

inline constexpr double kFishDecision = 0.1;  // s between decisions

class FishBody final : public SpringNetworkBody {
 public:
  FishBody(std::string name, const FishDesc& desc, const Material& material, std::uint64_t seed, int hook,
           double water_density);
  void step(StepContext& ctx) override;
  void show(SharedView& out, int self) override;
  bool view(BodyView& out) const override;
  void draw(DrawList& out) const override;
  void statistics(std::vector<Statistic>& out) const override;
  std::vector<std::string> notes(double h) const override;
  void hash(Hasher& h) const override;
  // A caught fish's mouth is held by the hook (the contact layer cannot move it), and what the
  // others see of the fish follows the contacts' corrections.
  void exportContacts(ContactExport& out) const override;
  bool meetsItself() const override { return true; }  // the fish of one body meet each other
  void importContacts(std::span<const Vec3> x, std::span<const Vec3> v) override;

  const FishDesc& desc() const { return desc_; }
  const FishTemplate& fishTemplate() const { return tmpl_; }
  std::size_t count() const { return motor_.size(); }
  FishFrame frame(std::size_t i) const;
  const FishMind& mind(std::size_t i) const { return mind_[i]; }
  const FishMotor& motor(std::size_t i) const { return motor_[i]; }
  bool caught(std::size_t i) const { return caught_[i] != 0; }
  // What the other fish and the food see of this body's fish, as of its last step.
  const std::vector<FishSighting>& sightings() const { return sightings_; }
  // The perception of fish i at the last decision (tests, docs).
  const Percept& percept(std::size_t i) const { return percept_[i]; }

 protected:
  void snapshotMore(StateWriter& w) const override;
  bool restoreMore(StateReader& r) override;

 private:
  friend Result<std::unique_ptr<Body>> buildFishBody(const BodyDesc& desc, const BuildContext& ctx);
  void decide(StepContext& ctx, int self);
  MotorCommand driveCommand(double t, FishMotor& m) const;
  void addPatterns(double t, FishMotor& m) const;
  void rollBalance();  // from frames_
  void waterDrag(const StepContext& ctx);
  void publishSightings(int self);

  FishDesc desc_;
  FishTemplate tmpl_;
  Material material_;
  std::uint64_t seed_ = 0;
  int hook_ = -1;  // the collider of the hook object
  std::vector<std::uint8_t> ignored_;  // per collider: 1 for the objects the fish do not steer around
  std::shared_ptr<const Image> skin_;  // the species' pattern

  // State (snapshots keep it).
  std::vector<FishMotor> motor_;
  std::vector<FishMind> mind_;
  std::vector<MotorCommand> command_;  // held between decisions
  std::vector<std::uint8_t> caught_;
  std::vector<Vec3> hook_point_;  // where a caught fish hangs, in the hook's authored frame
  std::int64_t decisions_ = 0;
  std::int64_t meals_ = 0;
  mutable std::vector<double> contact_inv_mass_;  // scratch: the nodes' inverse masses, 0 at hooked mouths
  int self_ = -1;  // this body's index among the world's bodies (what its sightings say), from show()

  // Scratch.
  std::vector<Percept> percept_;
  std::vector<FishSighting> sightings_;
  std::vector<FishFrame> frames_;  // each fish's frame at the start of the step
  std::vector<Vec3> external_;  // roll balance, N per node
  std::vector<Mat3> drag_;      // the water's drag at each node, kg/s (waterDrag)
  std::vector<Vec3> flow_;      // drag_ × the water's flow there, N
  std::vector<FishSighting> everyone_;
  BoxGrid grid_;
  std::vector<Collider> obstacles_;
};

// The builder of the registry row `fish`.
Result<std::unique_ptr<Body>> buildFishBody(const BodyDesc& desc, const BuildContext& ctx);

}  // namespace reel
