#include "sim/fish/food.h"

#include <algorithm>
#include <cmath>

#include "core/math.h"
#include "core/random.h"
#include "sim/draw_material.h"
#include "sim/water.h"

namespace reel {
namespace {

constexpr std::uint64_t kPlaceStream = 0xF00D, kJitterStream = 0xF00E;
constexpr double kJitterPeriod = 1.0;  // s: each particle picks a new swimming direction this often

}  // namespace

FoodBody::FoodBody(std::string name, const FoodDesc& desc, const Material& material, std::uint64_t seed)
    : Body(std::move(name)), desc_(desc), material_(material), seed_(seed) {
  emit(desc.initial);
}

void FoodBody::emit(std::int64_t upto) {
  while (emitted_ < upto) {
    if (static_cast<long long>(x_.size()) >= desc_.max_alive) {
      ++emitted_;  // the region is full: this one is not made
      continue;
    }
    const auto k = static_cast<std::uint64_t>(emitted_);
    const Vec3 u(uniformAt(seed_, kPlaceStream, 3 * k), uniformAt(seed_, kPlaceStream, 3 * k + 1),
                 uniformAt(seed_, kPlaceStream, 3 * k + 2));
    x_.push_back(desc_.min + u.cwiseProduct(desc_.max - desc_.min));
    v_.push_back(Vec3::Zero());
    id_.push_back(emitted_++);
  }
}

void FoodBody::show(SharedView& out, int self) { out.food.push_back({self, &x_, &id_, &meals_}); }

void FoodBody::step(StepContext& ctx) {
  meals_.clear();
  // Emission: `initial` at the start, then `rate` per second.
  emit(desc_.initial + static_cast<std::int64_t>(std::floor(desc_.rate * ctx.t1)));
  // Drift with the water, sinking slowly, each particle swimming a little in a direction that
  // changes every second.
  const std::int64_t epoch = static_cast<std::int64_t>(std::floor(ctx.t1 / kJitterPeriod));
  for (std::size_t i = 0; i < x_.size(); ++i) {
    const auto id = static_cast<std::uint64_t>(id_[i]);
    const std::uint64_t stream = kJitterStream ^ (static_cast<std::uint64_t>(epoch) << 20);
    const Vec3 swim = sphereDirection(uniformAt(seed_, stream, 2 * id), uniformAt(seed_, stream, 2 * id + 1));
    const Vec3 u = ctx.water ? ctx.water->at(x_[i], ctx.t1, *ctx.colliders) : Vec3::Zero();
    v_[i] = u + desc_.jitter * swim - Vec3(0, desc_.sink_speed, 0);
    x_[i] += ctx.h * v_[i];
  }
  // Eaten: for each biting mouth, body by body and fish by fish, the first particle (in the order
  // they were emitted) within its reach.
  std::vector<std::uint8_t> gone(x_.size(), 0);
  for (const SharedView::Fish& fish : ctx.shown->fish) {
    for (const FishSighting& f : *fish.sightings) {
      if (!f.biting) continue;
      const double bite = desc_.bite > 0 ? desc_.bite : 0.1 * f.length;  // the fish's length
      for (std::size_t i = 0; i < x_.size(); ++i)
        if (!gone[i] && (x_[i] - f.mouth).squaredNorm() < bite * bite) {
          gone[i] = 1;
          meals_.push_back({fish.body, f.index});
          ++eaten_;
          break;  // one particle per mouth per step
        }
    }
  }
  std::size_t k = 0;
  for (std::size_t i = 0; i < x_.size(); ++i)
    if (!gone[i]) x_[k] = x_[i], v_[k] = v_[i], id_[k] = id_[i], ++k;
  x_.resize(k), v_.resize(k), id_.resize(k);
}

Status FoodBody::checkState(const StepContext& ctx) const {
  return checkPoints(ctx, name(), "particle", x_, v_, StepBound{});
}

bool FoodBody::view(BodyView& out) const {
  out.name = name();
  out.type = "particles";
  out.generator = "food";
  out.positions = x_;
  out.velocities = v_;
  return true;
}

void FoodBody::snapshot(StateBlob& out) const {
  StateWriter w(out);
  w.put(x_), w.put(v_), w.put(id_), w.put(emitted_), w.put(eaten_), w.put(meals_);
}

bool FoodBody::restore(const StateBlob& in) {
  StateReader r(in);
  std::vector<Vec3> x, v;
  std::vector<std::int64_t> id;
  std::int64_t emitted = 0, eaten = 0;
  std::vector<FoodMeal> meals;
  r.get(x), r.get(v), r.get(id), r.get(emitted), r.get(eaten), r.get(meals);
  if (!r.done() || v.size() != x.size() || id.size() != x.size() || emitted < 0 || eaten < 0 ||
      static_cast<long long>(x.size()) > desc_.max_alive || !allWithin(x, kRunawayDistance) || !allWithin(v, kRunawaySpeed))
    return false;
  for (std::int64_t i : id)
    if (i < 0 || i >= emitted) return false;
  x_ = std::move(x), v_ = std::move(v), id_ = std::move(id), emitted_ = emitted, eaten_ = eaten, meals_ = std::move(meals);
  return true;
}

void FoodBody::hash(Hasher& h) const {
  h.add(std::span<const Vec3>(x_));
  h.add(std::span<const Vec3>(v_));
}

void FoodBody::draw(DrawList& out) const {
  DrawSpheres s;
  s.radius = static_cast<float>(desc_.size);
  s.material = drawMaterial(material_);
  appendPoints(s.centers, x_);
  if (!s.centers.empty()) out.spheres.push_back(std::move(s));
}

void FoodBody::statistics(std::vector<Statistic>& out) const {
  out.push_back({"alive", static_cast<double>(x_.size())});
  out.push_back({"eaten", static_cast<double>(eaten_)});
}

Result<std::unique_ptr<Body>> buildFoodBody(const BodyDesc& desc, const BuildContext& ctx) {
  return std::unique_ptr<Body>(std::make_unique<FoodBody>(desc.name, desc.as<FoodDesc>(), desc.material, ctx.seed));
}

}  // namespace reel
