// Cloth ↔ liquid, both ways: the contact layer's hook for a `fluid`'s particles against a
// `cloth`'s triangles (sim/contact_layer.h, ContactHook). The layer's broad phase finds each
// particle's candidate triangles (the sheet's grown by the adhesion range); the hook's law
// replaces the layer's own for the pair.
//
// After both have stepped, every particle within reach of a drawn triangle of the sheet (its
// contact radius plus the sheet's thickness, plus the adhesion range where the sheet's surface
// is sticky for its species) meets the closest one at its closest point, on the side it came
// from (the particle and the triangle at the start of the step): the pair is pushed apart to that reach,
// weighted by inverse masses (the point of the sheet moves its three nodes by its barycentric
// weights), and their relative velocity there takes one impulse J: restitution and Coulomb
// friction from the sheet's `surface` for the particle's species, adhesion pulling them
// together. The particle takes +J, the nodes −w_k·J, so cloth and liquid together keep their
// momentum exactly; pinned and gripped nodes pass their share to what holds them (the support
// force). The triangles, not only the nodes, stop particles, so none slips between the nodes of
// a coarse sheet; torn triangles are gone, and the liquid pours through the tear.
//
// A porous sheet (`porosity` p > 0) is a permeable membrane, after Darcy's law: instead of the
// push and the bounce, the relative normal velocity is damped implicitly with the time constant
// kSeepTime·p/(1 − p), so liquid seeps through at a speed proportional to the load pressing it.
// An absorbent sheet (`absorbency` > 0) soaks a touching particle up into the node of the
// triangle nearest to it while that node holds less than its capacity: the particle leaves the
// liquid and its mass and momentum join the node (perfectly inelastic); the sheet wicks and
// drains (cloth_wet.cpp), and a node holding a drop's mass beyond its capacity releases it as a
// new particle below itself, at its own velocity.
//
// Particles are resolved one after another in id order, after the layer's other contacts
// (deterministic for any thread count); a soaked-up particle leaves the liquid after the step
// (Body::dropPoints), and the drips follow (ContactHook::end).
#pragma once

#include <memory>

#include "sim/body.h"

namespace reel {

// The registry's interaction row (fluid, cloth): `liquid` is a FluidBody, `sheet` a ClothBody.
std::unique_ptr<ContactHook> clothLiquidHook(Body& liquid, Body& sheet);

}  // namespace reel
