// A mass-spring network as a body carries it: model, state, its system for the integrators, the
// integrator's workspace, its stable step and its contact radius. The shared part of every body
// made of nodes and springs (the springs kinds, cloth; fish and faces next).
#pragma once

#include <array>
#include <memory>
#include <span>
#include <vector>
#include <string>

#include "core/scene/mass_spring.h"
#include "core/state_blob.h"
#include "sim/body.h"
#include "sim/mass_spring.h"
#include "sim/stability.h"

namespace reel {

struct SpringNetwork {
  SpringNetwork() = default;
  // `system` refers to `model`: the network stays where it was built.
  SpringNetwork(const SpringNetwork&) = delete;
  SpringNetwork& operator=(const SpringNetwork&) = delete;
  MassSpringModel model;
  MassSpringState state;
  std::unique_ptr<MassSpringSystem> system;  // refers to `model`
  IntegratorWorkspace workspace;
  StepBound bound;      // of the scene's integrator
  double radius = 0.0;  // contact radius of the nodes, m
  double tolerance = kFilmTolerance;  // the kind's CG tolerance when the scene gives none

  // Builds model, state and system from explicit nodes and springs.
  void build(const MassSpringDesc& desc, const Vec3& gravity, IntegratorKind integrator, double contact_radius);
  // One step of the scene's integrator; an implicit solve that stops short is counted.
  void integrate(StepContext& ctx);
  // Contacts of the nodes with every object.
  void contacts(const StepContext& ctx);
  // Refusal of explicit Euler on undamped springs (its stable step is 0); empty when fine.
  std::string unstableMethod(const std::string& body, IntegratorKind integrator) const;
  StepLimit stepLimit(const std::string& body, IntegratorKind integrator) const;
  // Positions, velocities and the implicit solve's warm start.
  void snapshot(StateWriter& w) const;
  void restore(StateReader& r);
};

// A body made of one spring network: what the springs kinds and cloth share (and fish and faces
// will): its step bound, state check, dump view, hash, and the network's part of a snapshot.
class SpringNetworkBody : public Body {
 public:
  SpringNetworkBody(std::string name, std::string generator) : Body(std::move(name)), generator_(std::move(generator)) {}
  StepLimit stepLimit(IntegratorKind integrator) const override { return net_.stepLimit(name(), integrator); }
  std::ptrdiff_t parallelWork() const override { return static_cast<std::ptrdiff_t>(net_.model.nodes()); }
  Status checkState(const StepContext& ctx) const override;
  bool view(BodyView& out) const override;
  void hash(Hasher& h) const override;
  void snapshot(StateBlob& out) const override;
  bool restore(const StateBlob& in) override;
  // Its nodes (at the network's contact radius) and its surface meet every other body through the
  // World's contact layer.
  bool exportsContacts() const override { return true; }
  void exportContacts(ContactExport& out) const override;
  void importContacts(std::span<const Vec3> x, std::span<const Vec3> v) override;

  // The triangles over its nodes it meets others with, and which piece each node is (empty: one;
  // a fish, a kelp stalk: the contact layer searches piece by piece).
  void setSurface(std::vector<std::array<int, 3>> triangles, std::vector<int> pieces = {}) {
    surface_ = std::move(triangles);
    piece_ = std::move(pieces);
  }
  // The threads between its nodes it meets others with (a rope's segments, a kelp stalk's).
  void setEdges(std::vector<std::array<int, 2>> edges) { edges_ = std::move(edges); }

  SpringNetwork& network() { return net_; }
  const SpringNetwork& network() const { return net_; }
  const std::string& generator() const { return generator_; }

 protected:
  // What a kind adds to the network's state (cloth: its springs left and its sheet's state).
  virtual void snapshotMore(StateWriter&) const {}
  virtual bool restoreMore(StateReader&) { return true; }
  // The triangles and threads it meets others with: `surface_` and `edges_` unless overridden (a
  // sheet's intact triangles).
  virtual void exportSurface(ContactExport& out) const;
  SpringNetwork net_;
  std::vector<std::array<int, 3>> surface_;  // node indices, counter-clockwise from outside (triangles)
  std::vector<std::array<int, 2>> edges_;     // node indices (threads)
  std::vector<int> piece_;  // per node: which piece (a fish, a stalk); empty: one

 private:
  std::string generator_;  // the scene type that built it
};

// Builds the body's network from explicit nodes and springs; BadInput when the scene's explicit
// integrator has no stable step for it.
Status buildNetwork(SpringNetworkBody& body, const MassSpringDesc& nodes, const BodyDesc& desc, const BuildContext& ctx,
                    double contact_radius);

}  // namespace reel
