// The dfsph liquid model: divergence-free SPH (Bender & Koschier 2015, "Divergence-free smoothed
// particle hydrodynamics"; 2017, "Divergence-free SPH for incompressible and viscous fluids"). The
// particles keep the seed model's neighbour list, viscosity, nozzles, contacts and drawing; what
// pushes them apart is a pressure solved each step so that the liquid neither compresses (density
// solve) nor has its density change (divergence solve), instead of the pair force.
#pragma once

#include <vector>

#include "sim/collide.h"
#include "sim/fluid/fluid.h"

namespace reel {

// Samples of the wall table over [0, support].
inline constexpr int kWallTable = 256;

// The cubic spline kernel (Monaghan 1992) of support H (smoothing length H/2):
//   W(q) = σ(6q³ − 6q² + 1) for q = r/H ≤ ½,  2σ(1 − q)³ for ½ < q ≤ 1,  0 beyond;  σ = 8/(πH³).
double cubicKernel(double r, double H);
double cubicKernelSlope(double r, double H);  // dW/dr, 1/m⁴

// Sets the model up: the kernel's support (twice the largest species' spacing, the cube root of
// its volume mass/density), the species' volumes and the wall table: a flat wall at distance d
// fills the volume Φ(d) = ∫_d^H A(z) dz of the kernel, A(z) = 2π ∫_z^H W(r) r dr the kernel's
// integral over a plane at height z (Φ(0) = ½); dΦ/dd = −A(d).
void setupDfsph(Fluid& fl, const std::vector<double>& density);

// The kernel's volume a flat wall at distance d (from its surface) fills, Φ, and −dΦ/dd (`area`),
// with the wall taken fl.wall_offset farther (setupDfsph).
double wallVolume(const Fluid& fl, double d, double* area);

// One part of a step before the forces: densities and factors α at the positions now, then the
// divergence solve on the velocities (the step's velocity field made divergence-free).
void dfsphBegin(Fluid& fl, const std::vector<Collider>& colliders, double h);
// After the forces: the density solve on the predicted velocities v + h·f/m; the pressure's share
// joins the forces (f), so that the update that follows moves the particles by the solved velocity.
void dfsphPressure(Fluid& fl, double h);

}  // namespace reel
