// Spray, foam and air bubbles as diffuse particles carried from step to step: a drawing layer (the
// liquid's dynamics never see them), after Ihmsen, Akinci, Akinci & Teschner 2012, "Unified spray,
// foam and air bubbles for particle-based fluids" (The Visual Computer 28(6)). Their state is the
// liquid's (FluidState::diffuse_*), so the cache, a farm chunk and a resumed run draw them alike.
#pragma once

#include <cstdint>

#include "sim/fluid/fluid.h"

namespace reel {

// What a diffuse particle is by the liquid around it (Ihmsen et al. §4.3): spray has (almost) no
// liquid within the cutoff, an air bubble is inside the bulk, foam is between (at the surface).
enum class DiffuseKind : std::uint8_t { Spray = 0, Foam = 1, Bubble = 2 };

// How often the diffuse particles are advanced and seeded, s (a tick: stepDiffuse acts on the
// first step that ends a tick or more after the last time it did).
inline constexpr double kDiffuseTick = 1.0 / 120.0;
// At most this many at once (seeding waits while there are).
inline constexpr std::size_t kMaxDiffuse = 20000;

// The trapped-air potential of particle i, m/s (Ihmsen et al. §4.1):
//   I_ta = Σ_j |v_ij| (1 − v̂_ij·x̂_ij) W(x_ij),   W(r) = 1 − r/cutoff,
// large where neighbours rush past or into it (air folded in), not where they move along the line
// between them. Needs the neighbour list.
double trappedAir(const Fluid& fl, std::size_t i);

// Advances the diffuse particles to t1 when a tick has passed since their last update (`foam` > 0
// only): each is classified by its liquid neighbours and moves as its kind does (spray flies under
// gravity, foam rides the liquid's velocity, bubbles rise by buoyancy and are dragged along);
// spray and foam age and vanish at the end of their life; churned particles seed new ones. Called
// at the end of the liquid's step (its neighbour grid current). The same bits on any number of
// threads.
void stepDiffuse(Fluid& fl, const Vec3& gravity, double t1);

}  // namespace reel
