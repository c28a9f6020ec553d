#include "app/body_kinds.h"

#include "io/scene/readers.h"
#include "sim/articulated/articulated_body.h"
#include "sim/cloth/cloth_body.h"
#include "sim/coupling/cloth_liquid.h"
#include "sim/face/face_body.h"
#include "sim/fish/fish_body.h"
#include "sim/fish/food.h"
#include "sim/fish/seaweed.h"
#include "sim/fluid/fluid_body.h"
#include "sim/rigid/rigid_body.h"
#include "sim/school/school_body.h"
#include "sim/springs/springs_body.h"

namespace reel::app {
namespace {

// Seed streams: the mass-spring kinds share one (a cloth's tear thresholds), liquids, schools and
// the fish world's kinds have theirs.
constexpr std::uint64_t kSpringsStream = 0xC107, kFluidStream = 0xF1D0, kSchoolStream = 0x5C00, kFishStream = 0xF154,
                        kFoodStream = 0xF00D, kSeaweedStream = 0x5EA0,
                        kRigidStream = 0x816D, kFaceStream = 0xFACE, kArticulatedStream = 0xA871;

constexpr BodyKind kBodyKinds[] = {
    {"mass_spring", io::readMassSpringBody, buildMassSpringBody, kSpringsStream},
    {"rope", io::readRopeBody, buildRopeBody, kSpringsStream},
    {"net", io::readNetBody, buildNetBody, kSpringsStream},
    {"lattice", io::readLatticeBody, buildLatticeBody, kSpringsStream},
    {"cloth", io::readClothBody, buildClothBody, kSpringsStream},
    {"fluid", io::readFluidBody, buildFluidBody, kFluidStream},
    {"school", io::readSchoolBody, buildSchoolBody, kSchoolStream},
    {"fish", io::readFishBody, buildFishBody, kFishStream},
    {"food", io::readFoodBody, buildFoodBody, kFoodStream},
    {"seaweed", io::readSeaweedBody, buildSeaweedBody, kSeaweedStream},
    {"rigid", io::readRigidBody, buildRigidBody, kRigidStream, makeRigidSystem},
    {"face", io::readFaceBody, buildFaceBody, kFaceStream},
    {"articulated", io::readArticulatedBody, buildArticulatedBody, kArticulatedStream},
};

// Contact laws of pairs of kinds (the contact layer's hooks), in this order.
constexpr InteractionRow kInteractions[] = {
    {"fluid", "cloth", clothLiquidHook},
};

template <class Row, class F>
std::vector<Row> rows(F&& f) {
  std::vector<Row> out;
  for (const BodyKind& k : kBodyKinds) out.push_back(f(k));
  return out;
}

}  // namespace

std::span<const BodyKind> bodyKinds() { return kBodyKinds; }

std::span<const io::BodyReaderRow> bodyReaders() {
  static const auto r = rows<io::BodyReaderRow>([](const BodyKind& k) { return io::BodyReaderRow{k.type, k.read}; });
  return r;
}

std::span<const BodyKindRow> bodyBuilders() {
  static const auto r = rows<BodyKindRow>([](const BodyKind& k) { return BodyKindRow{k.type, k.build, k.seed_stream, k.system}; });
  return r;
}

Result<SceneDesc> loadScene(const std::string& path) { return io::loadScene(path, bodyReaders()); }
Result<SceneDesc> parseScene(const std::string& text, const std::string& file) {
  return io::parseScene(text, file, bodyReaders());
}
std::span<const InteractionRow> interactions() { return kInteractions; }

Result<World> makeWorld(const SceneDesc& scene, bool check_only) {
  return World::create(scene, bodyBuilders(), kInteractions, check_only);
}

}  // namespace reel::app
