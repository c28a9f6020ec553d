#include "sim/world.h"

#include <cmath>
#include <cstdio>
#include <sstream>

#include "core/camera.h"
#include "core/hash.h"
#include "core/math.h"
#include "core/mesh.h"
#include "core/parallel.h"
#include "core/random.h"
#include "sim/builders.h"

namespace reel {
namespace {

std::string fmt(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", x);
  return buf;
}

DrawMaterial drawMaterial(const Material& m) {
  DrawMaterial d;
  d.color = m.color;
  d.texture = m.texture_image;
  d.specular = m.specular;
  d.shininess = m.shininess;
  d.opacity = m.opacity;
  return d;
}

// The drawn shape of an object, in world space.
DrawMesh objectMesh(const ObjectDesc& o) {
  TriMesh m;
  switch (o.kind) {
    case ObjectKind::Plane:
      m = o.extent ? makeQuad((*o.extent)[0], (*o.extent)[1]) : makeQuad(400.0, 400.0);
      m.transform(rotationFromUp(o.normal), o.point);
      break;
    case ObjectKind::Sphere:
      m = makeUvSphere(o.radius, 48, 24);
      m.transform(Mat3::Identity(), o.center);
      break;
    case ObjectKind::Box:
      m = makeBox(o.size);
      m.transform(rotationFromEulerDeg(o.rotation_deg), o.center);
      break;
    case ObjectKind::Container: {
      // Floor and four walls, as five boxes in one mesh.
      for (const auto& [centre, size] : containerBoxes(o.size, o.wall)) {
        TriMesh part = makeBox(size);
        part.transform(Mat3::Identity(), centre);
        const auto base = static_cast<std::uint32_t>(m.vertexCount());
        m.positions.insert(m.positions.end(), part.positions.begin(), part.positions.end());
        m.normals.insert(m.normals.end(), part.normals.begin(), part.normals.end());
        m.uvs.insert(m.uvs.end(), part.uvs.begin(), part.uvs.end());
        for (std::uint32_t i : part.indices) m.indices.push_back(base + i);
      }
      m.transform(rotationFromEulerDeg(o.rotation_deg), o.center);
      break;
    }
    case ObjectKind::Capsule:
      m = makeCapsule(o.a, o.b, o.radius, 32, 16);
      break;
    case ObjectKind::Mesh:
      m = placeMesh(*o.mesh, o.scale, rotationFromEulerDeg(o.rotation_deg), o.position);
      break;
  }
  DrawMesh d;
  d.mesh = std::make_shared<const TriMesh>(std::move(m));
  d.material = drawMaterial(o.material);
  d.material.checker = o.checker;
  d.material.double_sided = o.kind == ObjectKind::Plane;
  return d;
}

// Without a `lights` list: a warm key light with soft shadows and a cool, soft ambient.
std::vector<LightDesc> defaultLights() {
  LightDesc key;
  key.kind = LightKind::Directional;
  key.direction = Vec3(-0.45, -1.0, -0.35);
  key.color = Vec3(1.0, 0.96, 0.9);
  key.intensity = 1.1;
  key.shadows = true;
  LightDesc amb;
  amb.kind = LightKind::Ambient;
  amb.color = Vec3(0.55, 0.62, 0.75);
  amb.intensity = 0.45;
  return {key, amb};
}

}  // namespace

Result<World> World::create(const SceneDesc& scene) {
  World w;
  w.integrator_ = scene.integrator;
  w.implicit_ = scene.implicit;
  w.fps_ = scene.fps;
  w.substeps_ = scene.substeps;
  // Mesh colliders find points up to their thickness plus the largest contact radius of any body,
  // plus, for a surface with adhesion, the largest liquid cutoff (adhesion pulls from that far).
  double radius = 0.0, adhesion_range = 0.0;
  for (const BodyDesc& bd : scene.bodies) {
    double r = bd.node_radius;
    if (const auto* cd = std::get_if<ClothDesc>(&bd.shape)) r = cd->thickness;
    if (const auto* fd = std::get_if<FluidDesc>(&bd.shape)) {
      r = fd->radius;
      for (const SpeciesDesc& sp : fd->species) adhesion_range = std::max(adhesion_range, sp.cutoff);
    }
    radius = std::max(radius, r);
  }
  const double h_max = 1.0 / (static_cast<double>(scene.fps) * scene.substeps);
  for (const ObjectDesc& o : scene.objects) {
    // A moving mesh also reaches as far as its fastest key moves it in one step.
    double speed = 0.0;
    for (std::size_t k = 1; k < o.motion.size(); ++k)
      speed = std::max(speed, (o.motion[k].position - o.motion[k - 1].position).norm() / (o.motion[k].time - o.motion[k - 1].time));
    if (!o.motion.empty()) w.moving_objects_.push_back(w.colliders_.size());
    if (!o.motion.empty() || o.dynamic) w.posed_objects_.push_back(w.colliders_.size());
    if (o.dynamic) w.dynamics_.push_back(makeDynamic(o, w.colliders_.size()));
    bool sticky = o.surface.adhesion > 0;
    for (const auto& [name, sf] : o.species_surface) sticky = sticky || sf.adhesion > 0;
    // A 2 cm margin for a step's motion.
    w.colliders_.push_back(makeCollider(o, radius + (sticky ? adhesion_range : 0.0) + 0.02 + speed * h_max));
    w.object_meshes_.push_back(objectMesh(o));
    w.object_pivots_.push_back(o.referencePoint());
  }
  w.wind_ = Wind(scene.wind, scene.seed);
  w.gravity_ = scene.gravity;
  w.camera_ = scene.camera;
  w.render_ = scene.render;
  w.lights_ = scene.has_lights ? scene.lights : defaultLights();

  const double h = 1.0 / (static_cast<double>(scene.fps) * scene.substeps);
  std::vector<std::string> errors;
  // A step above a body's stable bound is subdivided under auto_substeps; otherwise it is an error
  // naming what sets the bound (`what`) and what else would do (`instead`).
  auto boundStep = [&](const StepBound& bound, const std::string& what, const std::string& instead) {
    if (!(h > bound.h_max)) return;
    const double need = std::ceil(h / (0.9 * bound.h_max));
    if (scene.auto_substeps && need * scene.substeps <= kMaxStepsPerFrame) {
      w.inner_ = std::max(w.inner_, static_cast<int>(need));
      return;
    }
    const double min_sub = std::ceil(1.0 / (scene.fps * 0.9 * bound.h_max));
    errors.push_back(scene.file + ": /substeps: step h = 1/(fps·substeps) = " + fmt(h) + " s is above the stability bound " +
                     fmt(bound.h_max) + " s " + what + ": ω ≈ " + fmt(bound.omega) + " rad/s, β ≈ " + fmt(bound.beta) +
                     " 1/s); use \"substeps\": " + fmt(min_sub) + " or more, \"auto_substeps\": true, or " + instead);
  };
  for (const BodyDesc& bd : scene.bodies) {
    if (const auto* fd = std::get_if<FluidDesc>(&bd.shape)) {
      const std::uint64_t seed = splitmix64(scene.seed ^ (0xF1D0ull << 32) ^ static_cast<std::uint64_t>(w.fluids_.size()));
      auto fl = std::make_unique<Fluid>(buildFluid(*fd, bd.name, scene.objects, w.colliders_, seed));
      const StepBound bound = fluidStableStep(*fl);
      const auto S = static_cast<std::size_t>(fl->S);
      const auto pair = static_cast<std::size_t>(std::max(bound.node, 0));
      boundStep(bound, "of fluid '" + bd.name + "' (species '" + fl->species_names[pair / S] + "' with '" +
                           fl->species_names[pair % S] + "'",
                "softer alpha and beta (docs/fluids.md)");
      w.fluid_bounds_.push_back(bound);
      w.fluid_materials_.push_back(bd.material);
      w.fluids_.push_back(std::move(fl));
      continue;
    }
    auto b = std::make_unique<MassSpringBody>();
    b->name = bd.name;
    b->generator = bd.type;
    b->radius = bd.node_radius;
    b->material = bd.material;
    if (const auto* cd = std::get_if<ClothDesc>(&bd.shape)) {
      // Each body draws its random numbers from its own stream of the scene seed.
      b->cloth = std::make_unique<Cloth>();
      const std::uint64_t seed = splitmix64(scene.seed ^ (0xC107ull << 32) ^ static_cast<std::uint64_t>(w.bodies_.size()));
      buildMassSpring(buildCloth(*cd, seed, *b->cloth), scene.gravity, b->model, b->state);
      b->radius = cd->thickness;
    } else {
      buildMassSpring(expandBody(bd), scene.gravity, b->model, b->state);
    }
    b->dynamics = std::make_unique<MassSpringDynamics>(b->model);
    b->bound = stableStep(b->model, scene.integrator);
    if (b->bound.h_max <= 0) {
      errors.push_back(scene.file + ": /integrator: explicit_euler is unstable for body '" +
                       bd.name + "': its springs are undamped (stable step bound 0); add spring "
                       "or node damping, or use symplectic_euler, verlet, rk4 or implicit_euler");
    } else {
      boundStep(b->bound, "of " + std::string(integratorName(scene.integrator)) + " for body '" + bd.name + "' (node " +
                              std::to_string(b->bound.node),
                "implicit_euler");
    }
    w.bodies_.push_back(std::move(b));
  }
  if (!errors.empty()) return Error(ErrorKind::BadInput, std::move(errors));
  return w;
}

Status World::checkState(const std::string& name, const char* what_kind, const std::vector<Vec3>& x,
                         const std::vector<Vec3>& v, const StepBound& bound, long long step) const {
  auto bad = [&](std::ptrdiff_t i) {
    const double s = v[i].squaredNorm(), r = x[i].squaredNorm();
    // NaN fails every comparison, so test for the good case.
    return !(s <= kRunawaySpeed * kRunawaySpeed && r <= kRunawayDistance * kRunawayDistance);
  };
  const auto n = static_cast<std::ptrdiff_t>(x.size());
  if (deterministicSum(n, [&](std::ptrdiff_t i) { return bad(i) ? 1.0 : 0.0; }) == 0.0) return {};
  std::ptrdiff_t i = 0;
  while (!bad(i)) ++i;
  std::string what;
  if (!x[i].allFinite())
    what = "position is not finite";
  else if (!v[i].allFinite())
    what = "velocity is not finite";
  else if (v[i].norm() > kRunawaySpeed)
    what = "speed " + fmt(v[i].norm()) + " m/s ran away (limit " + fmt(kRunawaySpeed) + " m/s)";
  else
    what = "position ran away (|x| = " + fmt(x[i].norm()) + " m)";
  const double t = static_cast<double>(step) / (static_cast<double>(fps_) * stepsPerFrame());
  std::string hint = "step h = " + fmt(stepSize()) + " s";
  if (std::isfinite(bound.h_max))
    hint += ", estimated stable bound " + fmt(bound.h_max) + " s; try more substeps" +
            (std::string(what_kind) == "node" ? " or implicit_euler" : "");
  else
    hint += "; try more substeps, more damping or softer springs";
  return Error(ErrorKind::Unstable, "unstable at frame " + std::to_string(frame_ + 1) + " (t = " +
                                        fmt(t) + " s): body '" + name + "' " + what_kind + " " +
                                        std::to_string(i) + " " + what + " (" + hint + ")");
}

Status World::advanceFrame() {
  const double h = stepSize();
  const int steps = stepsPerFrame();
  const double per_step = 1.0 / (static_cast<double>(fps_) * steps);
  for (int s = 0; s < steps; ++s) {
    const double t0 = static_cast<double>(step_) * per_step;
    ++step_;
    const double t1 = static_cast<double>(step_) * per_step;
    // Moving objects take their pose at the end of the step; contacts see their velocity.
    for (std::size_t o : moving_objects_) colliders_[o].moveTo(t1, h);
    for (auto& b : bodies_) {
      Cloth* cloth = b->cloth.get();
      if (cloth) {
        gripVelocities(*cloth, t0, b->state.v);
        const AirDesc& air = cloth->air;
        if (air.viscous != 0.0 || air.drag != 0.0 || air.lift != 0.0) {
          airForces(*cloth, wind_, t0, b->state.x, b->state.v);
          b->dynamics->setExternalForces(cloth->f_air.data());
        }
      }
      integrate(integrator_, *b->dynamics, b->state.x, b->state.v, h, b->workspace, implicit_, &stats_);
      if (cloth) {
        gripPositions(*cloth, t1, b->state.x);
        limitStrain(*cloth, b->model, h, b->state.x, b->state.v);
        if (cloth->self_collision) selfCollide(*cloth, b->model, b->state.x, b->state.v);
      }
      if (integrator_ == IntegratorKind::ImplicitEuler && stats_.cg_relative_residual > implicit_.cg_tolerance) {
        ++cg_unconverged_;
        cg_worst_ = std::max(cg_worst_, stats_.cg_relative_residual);
      }
      resolveContacts(colliders_, b->radius, h, b->model.fixed.data(), b->state.x, b->state.v);
      if (cloth) tearSprings(*cloth, b->model, b->state.x);
      if (Status st = checkState(b->name, "node", b->state.x, b->state.v, b->bound, step_); !st) return st;
    }
    for (std::size_t f = 0; f < fluids_.size(); ++f) {
      Fluid& fl = *fluids_[f];
      stepFluid(fl, colliders_, dynamics_, gravity_, h, t0, t1);
      if (Status st = checkState(fl.name, "particle", fl.x, fl.v, fluid_bounds_[f], step_); !st) return st;
    }
    for (DynamicObject& d : dynamics_) stepDynamic(d, colliders_, gravity_, h);
  }
  ++frame_;
  return {};
}

void World::snapshot(FrameSnapshot& out) const {
  out.frame = frame_;
  out.time = time();
  out.bodies.clear();
  for (const auto& b : bodies_) {
    BodySnapshot s;
    s.name = b->name;
    s.type = "mass_spring";
    s.generator = b->generator;
    s.positions = b->state.x;
    s.velocities = b->state.v;
    s.spring_a = b->model.springs.a;
    s.spring_b = b->model.springs.b;
    out.bodies.push_back(std::move(s));
  }
  for (const auto& fl : fluids_) {
    BodySnapshot s;
    s.name = fl->name;
    s.type = "particles";
    s.generator = "fluid";
    fluidById(*fl);  // particles in order of creation, whatever slots they sit in
    s.positions = fl->x_by_id;
    s.velocities = fl->v_by_id;
    s.species = fl->s_by_id;
    s.species_names = fl->species_names;
    out.bodies.push_back(std::move(s));
  }
}

void World::emit(DrawList& out) const {
  out.camera = cameraAt(camera_, time());
  out.lights = lights_;
  out.background_top = render_.background_top;
  out.background_bottom = render_.background_bottom;
  out.fog_color = render_.fog_color;
  out.fog_density = render_.fog_density;
  out.tonemap = render_.tonemap;
  out.clearGeometry();
  out.meshes = object_meshes_;
  // Moving objects: their authored mesh carried to the current pose.
  for (std::size_t o : posed_objects_) {
    const Collider& c = colliders_[o];
    TriMesh m = *object_meshes_[o].mesh;
    const Vec3 shift = c.pos - c.rot * object_pivots_[o];
    m.transform(c.rot, shift);
    out.meshes[o].mesh = std::make_shared<const TriMesh>(std::move(m));
    out.meshes[o].per_frame = true;
  }
  for (const auto& b : bodies_) {
    if (b->cloth) {
      DrawMesh sheet;
      sheet.mesh = std::make_shared<const TriMesh>(clothMesh(*b->cloth, b->state.x));
      sheet.per_frame = true;
      sheet.material = drawMaterial(b->material);
      sheet.material.double_sided = true;
      if (sheet.mesh->triangleCount() > 0) out.meshes.push_back(std::move(sheet));
      continue;
    }
    DrawSpheres nodes;
    nodes.radius = static_cast<float>(b->radius);
    nodes.material = drawMaterial(b->material);
    nodes.centers.reserve(3 * b->state.x.size());
    for (const Vec3& p : b->state.x)
      for (int k = 0; k < 3; ++k) nodes.centers.push_back(static_cast<float>(p[k]));
    DrawTubes springs;
    springs.radius = static_cast<float>(0.35 * b->radius);
    springs.material = nodes.material;
    const Springs& s = b->model.springs;
    springs.ends.reserve(6 * s.size());
    for (std::size_t k = 0; k < s.size(); ++k)
      for (const Vec3* p : {&b->state.x[static_cast<std::size_t>(s.a[k])], &b->state.x[static_cast<std::size_t>(s.b[k])]})
        for (int c = 0; c < 3; ++c) springs.ends.push_back(static_cast<float>((*p)[c]));
    out.spheres.push_back(std::move(nodes));
    if (!springs.ends.empty()) out.tubes.push_back(std::move(springs));
  }
  for (std::size_t f = 0; f < fluids_.size(); ++f) emitFluid(*fluids_[f], fluid_materials_[f], out);
}

std::uint64_t World::stateHash() const {
  Hasher h;
  for (const auto& b : bodies_) {
    h.add(std::span<const Vec3>(b->state.x));
    h.add(std::span<const Vec3>(b->state.v));
  }
  for (const auto& fl : fluids_) {
    fluidById(*fl);
    h.add(std::span<const Vec3>(fl->x_by_id));
    h.add(std::span<const Vec3>(fl->v_by_id));
  }
  for (const DynamicObject& d : dynamics_) {
    const Collider& c = colliders_[d.collider];
    const Vec3 state[4] = {c.pos, d.v, d.w, c.rot.col(0) + 2.0 * c.rot.col(1)};
    h.add(std::span<const Vec3>(state, 4));
  }
  return h.h;
}

}  // namespace reel
