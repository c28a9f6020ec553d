// The `fluid` kind's reader: species, interactions, blocks, particles, nozzles, limits and look.
#include <algorithm>
#include <memory>

#include "core/scene/fluid.h"
#include "io/scene/reader.h"
#include "io/scene/readers.h"

namespace reel::io {
namespace {

// Particles one machine holds: half its memory at about 1 KiB per particle (state, neighbour
// list, drawing), at most 50 million.
long long defaultMaxParticles() { return itemsInMemory(0.5, 1024, 10'000, 50'000'000, 4'000'000); }

// A species named by `key` (default: the first), as an index.
int readSpecies(Obj& o, const std::vector<std::string>& names, const std::string& key = "species") {
  if (names.empty()) return 0;
  const std::string n = o.choice(key, names[0], names);
  const auto it = std::find(names.begin(), names.end(), n);
  return it == names.end() ? 0 : static_cast<int>(it - names.begin());
}

// What reading a liquid's lists gathers on the way.
struct FluidReading {
  FluidDesc& fd;
  std::vector<std::string> names;  // species, in order
  double total = 0.0;              // particles from blocks, lists and emitters
  double min_spacing = 0.0;        // m, the finest block
  double duration = 0.0;           // s, the scene's (emitters stop by then)
  double sph_spacing = 0.0;        // m, the dfsph model's particle spacing (0: the pair model)
};

void readSpeciesEntry(Obj& so, FluidReading& r) {
  Diagnostics& d = so.diag();
  SpeciesDesc sp;
  sp.path = so.path();
  sp.name = so.string("name", true).value_or("");
  if (so.ok() && sp.name.empty() && so.has("name")) d.error(childPath(so.path(), "name"), "must not be empty");
  if (std::find(r.names.begin(), r.names.end(), sp.name) != r.names.end())
    d.error(childPath(so.path(), "name"), "duplicate species \"" + sp.name + "\"");
  sp.mass = so.number("mass", sp.mass, kPos);
  sp.alpha = so.number("alpha", sp.alpha, kNonNeg);
  sp.beta = so.number("beta", sp.beta, kNonNeg);
  sp.a = so.number("a", sp.a, Range{0.0, 16.0, true, false});
  sp.b = so.number("b", sp.b, Range{0.0, 16.0, true, false});
  sp.epsilon = so.number("epsilon", sp.epsilon, kNonNeg);
  sp.cutoff = so.number("cutoff", sp.cutoff, Range{0.0, 10.0, true, false});
  sp.viscosity = so.number("viscosity", sp.viscosity, kNonNeg);
  sp.agitation = so.number("agitation", sp.agitation, Range::closed(0.0, 100.0));
  if (sp.agitation > 0 && sp.viscosity == 0)
    d.error(childPath(so.path(), "agitation"), "needs viscosity > 0 (the random kicks and the viscous drag balance at the thermal speed)");
  if (r.fd.model == LiquidModel::Dfsph) {
    // Pressure keeps the particles apart: no pair force, and the kernel sets the reach.
    for (const char* key : {"alpha", "beta", "a", "b", "epsilon", "cutoff"})
      if (so.has(key))
        d.error(childPath(so.path(), key), "the dfsph model has no pair force (its particles' spacing is (mass/density)^(1/3), its reach twice that): leave it out, or use \"model\": \"pairs\"");
    sp.density = so.number("density", sp.density, Range{1e-3, 1e5, true, true});
  } else if (so.has("density")) {
    d.error(childPath(so.path(), "density"), "only the dfsph model has a rest density (the pair model's is set by its forces): add \"model\": \"dfsph\" to the liquid");
  }
  sp.color = so.vec3("color", sp.color, kNonNeg);
  if (so.has("transmission")) sp.transmission = so.number("transmission", 0.0, kUnit);
  if (sp.alpha > 0 && sp.beta == 0)
    d.error(childPath(so.path(), "beta"), "must be > 0 when alpha > 0 (attraction without repulsion collapses the liquid)");
  r.names.push_back(sp.name);
  r.fd.species.push_back(sp);
}

void readInteractionEntry(Obj& io, FluidReading& r) {
  Diagnostics& d = io.diag();
  InteractionDesc in;
  in.path = io.path();
  const Json* pair = io.raw("species");
  const std::string pp = childPath(io.path(), "species");
  if (!pair) {
    if (io.ok()) d.error(pp, "missing required key");
  } else if (!pair->is_array() || pair->size() != 2 || !(*pair)[0].is_string() || !(*pair)[1].is_string()) {
    d.error(pp, "expected two species names, got " + typeName(*pair));
  } else {
    int idx[2] = {0, 0};
    for (int k = 0; k < 2; ++k) {
      const std::string n = (*pair)[static_cast<std::size_t>(k)].get<std::string>();
      const auto it = std::find(r.names.begin(), r.names.end(), n);
      if (it == r.names.end()) {
        const std::string near = nearest(n, r.names);
        d.error(childPath(pp, static_cast<std::size_t>(k)),
                "unknown species \"" + n + "\"" + (near.empty() ? "" : " (did you mean \"" + near + "\"?)"));
      } else {
        idx[k] = static_cast<int>(it - r.names.begin());
      }
    }
    in.s = idx[0];
    in.t = idx[1];
  }
  auto opt = [&](const char* key, Range range) -> std::optional<double> { return io.number(key, range); };
  in.alpha = opt("alpha", kNonNeg);
  in.beta = opt("beta", kNonNeg);
  in.a = opt("a", Range{0.0, 16.0, true, false});
  in.b = opt("b", Range{0.0, 16.0, true, false});
  in.epsilon = opt("epsilon", kNonNeg);
  in.cutoff = opt("cutoff", Range{0.0, 10.0, true, false});
  in.viscosity = opt("viscosity", kNonNeg);
  if (r.fd.model == LiquidModel::Dfsph)
    for (const char* key : {"alpha", "beta", "a", "b", "epsilon", "cutoff"})
      if (io.has(key)) d.error(childPath(io.path(), key), "the dfsph model has no pair force: only \"viscosity\" may be set between species");
  r.fd.interactions.push_back(in);
}

void readBlockEntry(Obj& bo, FluidReading& r) {
  Diagnostics& d = bo.diag();
  FluidBlockDesc b;
  b.species = readSpecies(bo, r.names);
  b.min = bo.vec3("min", Range::any(), true).value_or(b.min);
  b.max = bo.vec3("max", Range::any(), true).value_or(b.max);
  b.spacing = bo.number("spacing", kPos, true).value_or(b.spacing);
  b.jitter = bo.number("jitter", 0.0, Range::closed(0.0, 0.5));
  b.velocity = bo.vec3("velocity", b.velocity);
  if ((b.max - b.min).minCoeff() <= 0) d.error(childPath(bo.path(), "max"), "must be above min on every axis");
  else {
    const double n = b.count();
    if (n > static_cast<double>(r.fd.max_particles))
      d.error(bo.path(), "holds " + (n < 1e15 ? std::to_string(static_cast<long long>(n)) : std::string("over 10^15")) +
                             " particles, more than max_particles = " + std::to_string(r.fd.max_particles));
    r.total += n;
    if (r.total > static_cast<double>(defaultMaxParticles()) * 4)  // far beyond any limit: stop counting
      r.total = static_cast<double>(defaultMaxParticles()) * 4;
  }
  // A dfsph block packed closer than its particles' spacing starts compressed: its pressure would
  // blow it apart.
  const double rest = r.fd.model == LiquidModel::Dfsph && b.species < static_cast<int>(r.fd.species.size())
                          ? r.fd.species[static_cast<std::size_t>(b.species)].spacing()
                          : 0.0;
  if (b.spacing < 0.95 * rest)
    d.error(childPath(bo.path(), "spacing"), "packs the dfsph species closer than its spacing (mass/density)^(1/3) = " +
                                                 std::to_string(rest) + " m: the block would start compressed");
  r.min_spacing = r.min_spacing > 0 ? std::min(r.min_spacing, b.spacing) : b.spacing;
  r.fd.blocks.push_back(b);
}

void readParticlesEntry(Obj& po, FluidReading& r) {
  Diagnostics& d = po.diag();
  FluidParticlesDesc pd;
  pd.species = readSpecies(po, r.names);
  for (const char* key : {"positions", "velocities"}) {
    const Json* j = po.raw(key);
    const std::string kp = childPath(po.path(), key);
    if (!j) {
      if (std::string(key) == "positions" && po.ok()) d.error(kp, "missing required key");
      continue;
    }
    if (!j->is_array() || j->size() > 10'000'000) {
      d.error(kp, "expected a list of [x, y, z], got " + typeName(*j));
      continue;
    }
    auto& out = std::string(key) == "positions" ? pd.positions : pd.velocities;
    for (std::size_t k = 0; k < j->size(); ++k)
      if (auto v = readVec3((*j)[k], childPath(kp, k), d, Range::any())) out.push_back(*v);
  }
  if (!pd.velocities.empty() && pd.velocities.size() != pd.positions.size())
    d.error(childPath(po.path(), "velocities"), "must list one velocity per position (" +
                                                std::to_string(pd.positions.size()) + "), got " +
                                                std::to_string(pd.velocities.size()));
  r.total += static_cast<double>(pd.positions.size());
  r.fd.particles.push_back(std::move(pd));
}

void readEmitterEntry(Obj& eo, FluidReading& r) {
  Diagnostics& d = eo.diag();
  EmitterDesc e;
  e.species = readSpecies(eo, r.names);
  e.position = eo.vec3("position", Range::any(), true).value_or(e.position);
  e.direction = eo.vec3("direction", e.direction);
  if (e.direction.norm() == 0) d.error(childPath(eo.path(), "direction"), "must not be the zero vector");
  else e.direction.normalize();
  e.speed = eo.number("speed", e.speed, Range{0.0, 1e3, true, false});
  e.radius = eo.number("radius", e.radius, Range{0.0, 100.0, true, false});
  e.rate = eo.number("rate", kPos, true).value_or(e.rate);
  e.start = eo.number("start", 0.0, kNonNeg);
  e.stop = std::min(eo.number("stop", r.duration, kNonNeg), r.duration);
  e.spacing = eo.number("spacing", r.sph_spacing > 0 ? r.sph_spacing : 2.0 * r.fd.radius, Range{0.0, 100.0, true, false});
  if (e.spacing < 0.95 * r.sph_spacing)
    d.error(childPath(eo.path(), "spacing"), "packs the dfsph liquid closer than its spacing (mass/density)^(1/3) = " +
                                                 std::to_string(r.sph_spacing) + " m: its layers would leave compressed");
  e.nozzle = eo.boolean("nozzle", e.nozzle);
  if (e.stop <= e.start) {
    d.error(childPath(eo.path(), "stop"), "must be after start (and start before the scene ends)");
    e.stop = e.start;
  } else if (e.radius / e.spacing > 200) {
    d.error(childPath(eo.path(), "radius"), "holds too many particles per layer for its spacing");
  } else {
    // Layers leave perLayer()/rate s apart and travel speed × that: they must not overlap.
    const double gap = e.speed * static_cast<double>(e.perLayer()) / e.rate;
    if (gap < 0.5 * e.spacing)
      d.error(childPath(eo.path(), "rate"), "packs its layers " + std::to_string(gap) + " m apart, closer than half the spacing (" +
                                                 std::to_string(0.5 * e.spacing) + " m): lower the rate, or raise speed or radius");
    else
      r.total += e.layerCount() * static_cast<double>(e.perLayer());
  }
  r.fd.emitters.push_back(e);
}

void readFluid(Obj& o, FluidDesc& fd, double duration) {
  Diagnostics& d = o.diag();
  const std::string& p = o.path();
  FluidReading r{fd, {}, 0.0, 0.0, duration};
  fd.model = o.choice("model", "pairs", {"pairs", "dfsph"}) == "dfsph" ? LiquidModel::Dfsph : LiquidModel::Pairs;
  readList(o, "species", [&](Obj& e) { readSpeciesEntry(e, r); }, true);
  if (fd.model == LiquidModel::Dfsph && !fd.species.empty()) {
    // The viscosity (and adhesion to objects) reach as far as the kernel.
    const double support = 2.0 * fd.sphSpacing();
    for (std::size_t k = 0; k < fd.species.size(); ++k) {
      SpeciesDesc& sp = fd.species[k];
      sp.cutoff = support;
      // One kernel serves every species: a much finer one would have hundreds of neighbours.
      if (sp.spacing() < 0.5 * fd.sphSpacing())
        d.error(childPath(childPath(p, "species"), k), "is spaced " + std::to_string(sp.spacing()) +
                                                         " m, under half the coarsest species' " + std::to_string(fd.sphSpacing()) +
                                                         " m: dfsph species share one kernel (give them like spacings)");
    }
  }
  if (o.ok() && o.raw("species") && fd.species.empty()) d.error(childPath(p, "species"), "needs at least one species");
  readList(o, "interactions", [&](Obj& e) { readInteractionEntry(e, r); });
  const long long limit = o.integer("max_particles", 1ll, 50'000'000ll).value_or(0);
  // (dfsph keeps its neighbours inside the kernel's reach with a vector each besides: about 2 KiB a particle)
  fd.max_particles = limit > 0 ? limit : defaultMaxParticles() / (fd.model == LiquidModel::Dfsph ? 2 : 1);
  readList(o, "blocks", [&](Obj& e) { readBlockEntry(e, r); });
  readList(o, "particles", [&](Obj& e) { readParticlesEntry(e, r); });
  // dfsph: just under half its spacing, so a block's outer layer clears the walls it fills to.
  const double sph_spacing = fd.model == LiquidModel::Dfsph && !fd.species.empty() ? fd.sphSpacing() : 0.0;
  fd.radius = o.number("radius", sph_spacing > 0 ? 0.48 * std::min(sph_spacing, r.min_spacing > 0 ? r.min_spacing : sph_spacing)
                                                 : (r.min_spacing > 0 ? 0.5 * r.min_spacing : fd.radius),
                       Range{0.0, 10.0, true, false});
  r.sph_spacing = sph_spacing;
  readList(o, "emitters", [&](Obj& e) { readEmitterEntry(e, r); });
  if (r.total > static_cast<double>(fd.max_particles))
    d.error(p, "would hold " + (r.total >= static_cast<double>(defaultMaxParticles()) * 4 ? std::string("far more") : std::to_string(static_cast<long long>(r.total))) +
                   " particles (blocks, particles and emitters), more than max_particles = " + std::to_string(fd.max_particles));
  if (o.ok() && r.total == 0 && fd.emitters.empty()) d.error(p, "has no particles: give blocks, particles or emitters");
  const std::string draw = o.choice("draw", "spheres", {"spheres", "surface"});
  fd.draw = draw == "surface" ? FluidDraw::Surface : FluidDraw::Spheres;
  fd.surface_cell = o.number("surface_cell", 0.0, Range::closed(0.0, 10.0));
  fd.surface_kernel = o.number("surface_kernel", 0.0, Range::closed(0.0, 10.0));
  fd.surface_iso = o.number("surface_iso", fd.surface_iso, Range{0.0, 10.0, true, false});
  fd.surface_anisotropic = o.choice("surface_kernels", "anisotropic", {"anisotropic", "isotropic"}) == "anisotropic";
  fd.surface_smoothing = o.integer("surface_smoothing", fd.surface_smoothing, 0, 20);
  fd.foam = o.number("foam", 0.0, Range::closed(0.0, 1.0));
  fd.foam_life = o.number("foam_life", fd.foam_life, Range::closed(0.05, 60.0));
  fd.shutter = o.number("shutter", fd.shutter, Range::closed(0.0, 1.0));
  if (fd.surface_cell > 0 && fd.surface_kernel > 0 && fd.surface_kernel / fd.surface_cell > 16)
    d.error(childPath(p, "surface_kernel"), "must be at most 16 surface cells");
  if (fd.surface_cell == 0 && fd.surface_kernel > 0 && fd.surface_kernel / fd.radius > 16)
    d.error(childPath(p, "surface_kernel"), "must be at most 16 particle radii");
}

}  // namespace

std::shared_ptr<const BodyParams> readFluidBody(Obj& o, BodyDesc& body, const SceneDesc& scene) {
  auto fd = std::make_shared<FluidDesc>();
  readFluid(o, *fd, scene.duration);
  body.material.specular = 0.5;   // liquids reflect water's 4% unless told otherwise,
  body.material.roughness = 0.08; // from a nearly smooth surface
  return fd;
}

}  // namespace reel::io
