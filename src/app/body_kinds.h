// The registry of body kinds: one row per kind, in the one layer that sees both io and sim. A row
// pairs the kind's scene name with its reader (io/scene/<kind>.cpp) and its builder
// (sim/<kind>/); the kind names exist here once. Adding a kind: its folders, and a row here.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "io/scene_loader.h"
#include "sim/world.h"

namespace reel::app {

struct BodyKind {
  const char* type;        // the scene's `type`
  io::BodyReader read;     // its keys → its description
  BodyBuilder build;       // its description → a Body
  std::uint64_t seed_stream;  // tag of the seed stream its bodies draw from (sim/body.h)
  SystemBuilder system = nullptr;  // the World's system that steps its bodies together, if any
};

std::span<const BodyKind> bodyKinds();
std::span<const io::BodyReaderRow> bodyReaders();
std::span<const BodyKindRow> bodyBuilders();
// The contact laws of pairs of kinds (the contact layer's hooks), in order.
std::span<const InteractionRow> interactions();

// The scene and the world with every kind reel has.
Result<SceneDesc> loadScene(const std::string& path);
Result<SceneDesc> parseScene(const std::string& text, const std::string& file);
// `check_only`: for `reel check`, never stepped (World::create).
Result<World> makeWorld(const SceneDesc& scene, bool check_only = false);

}  // namespace reel::app
