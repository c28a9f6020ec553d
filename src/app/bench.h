// The benchmarks of simulation (reel bench springs cloth fluid school fish rigid), in
// bench_sim.cpp; the rendering ones and the dispatcher are in bench.cpp.
#pragma once

namespace reel::app {

void benchSprings(double seconds);
int benchCloth(double simulated_64);
int benchFluid(double simulated);
int benchSchool(double seconds);
int benchFish(double seconds);
int benchRigid();
int benchArticulated();
int benchClothLiquid();
int benchFace();
// bench_cache.cpp: the farm cache's bytes per node/particle/agent by kind, after `frames` frames.
int benchCache(int frames);

}  // namespace reel::app
