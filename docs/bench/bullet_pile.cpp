// Bullet Physics box-pile benchmark, for comparison with `reel bench rigid`.
//
// Build (Debian 12: apt-get install libbullet-dev, Bullet 3.24, single precision):
//   g++ -O2 -std=c++17 docs/bench/bullet_pile.cpp -I/usr/include/bullet -lBulletDynamics -lBulletCollision -lLinearMath -o /tmp/bullet_pile
// Run:
//   /tmp/bullet_pile                 # 1000 boxes
//   /tmp/bullet_pile 100             # N boxes, N a positive multiple of 100
//   /tmp/bullet_pile 1000 --no-sleep # same, with sleeping switched off
//
// Scene (the same pile that `reel bench rigid` runs):
//   - gravity (0, -9.81, 0); static ground plane y = 0 (btStaticPlaneShape),
//     friction 0.5, restitution 0.
//   - N cubes of edge 0.5 m (btBoxShape, half extents 0.25, Bullet's default
//     0.04 m collision margin, which btBoxShape keeps inside the half extents),
//     density 1000 kg/m^3 -> mass 125 kg, inertia from calculateLocalInertia
//     (m * a^2 / 6 = 5.2083 kg m^2 about each axis), friction 0.5,
//     restitution 0, linear and angular damping 0.
//   - Grid 10 x (N/100) x 10 in (x, y, z). Box index i runs x fastest, then z,
//     then y (layer):  ix = i % 10,  iz = (i / 10) % 10,  iy = i / 100.
//     Centre: x = (ix - 4.5) * 0.75,  z = (iz - 4.5) * 0.75,  y = 0.3 + iy * 0.55
//     (grid centred on x = z = 0, lowest layer's centres at y = 0.3).
//   - Box i is turned about +y (right-handed, i.e. counter-clockwise seen from
//     above) by 7 deg * ((i * 37) mod 13), i.e. 0..84 deg, so the boxes do not
//     land perfectly aligned.
//
// World: btDefaultCollisionConfiguration, btCollisionDispatcher,
// btDbvtBroadphase, btSequentialImpulseConstraintSolver,
// btDiscreteDynamicsWorld (single-threaded). Solver: m_numIterations = 10
// (also Bullet's default); all other btContactSolverInfo fields left at
// Bullet's defaults, which means split impulse ON (m_splitImpulse = 1,
// m_splitImpulsePenetrationThreshold = -0.04, m_erp2 = 0.2).
// Sleeping: left as Bullet does it by default, i.e. ENABLED: a simulation
// island is put to sleep once every body in it has stayed below 0.8 m/s
// linear and 1.0 rad/s angular speed for gDeactivationTime = 2 s; Bullet then
// zeroes the sleeping bodies' velocities and skips them until woken.
// The optional flag --no-sleep (not part of the reference scene) sets
// gDisableDeactivation = true so that every box is simulated for all 600 steps
// and final_max_speed reports real residual motion.
//
// Stepping: stepSimulation(h, 0) with h = 1/120 s, 600 times (5 s simulated).
// maxSubSteps = 0 makes Bullet take exactly one step of length h per call,
// with no fixed-step accumulator and no motion-state interpolation.
//
// Measured: steady_clock wall time of the 600 stepSimulation calls only
// (setup, contact counting and teardown are not timed). After each step the
// contact points are counted as the sum over the dispatcher's persistent
// manifolds of getNumContacts() (Bullet's cached points, including ones kept
// within the contact breaking threshold and those of sleeping pairs).
// At the end: the largest linear speed of any box, the mean height (y) of the
// box centres, and how many boxes are asleep.
//
// Output, one JSON line:
//   {"name": "bullet_pile", "boxes": N, "steps": 600, "h": 0.008333,
//    "seconds": ..., "steps_per_s": ..., "contacts_per_s": ...,
//    "mean_contacts": ..., "final_max_speed": ..., "final_mean_height": ...,
//    "asleep": ..., "sleeping_enabled": true|false}
// contacts_per_s = (sum of the per-step contact counts) / seconds;
// mean_contacts = that sum / 600.

#include <btBulletDynamicsCommon.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <vector>

namespace {

constexpr int kSteps = 600;
constexpr double kH = 1.0 / 120.0;
constexpr double kEdge = 0.5;
constexpr double kDensity = 1000.0;
constexpr double kFriction = 0.5;
constexpr double kPi = 3.14159265358979323846;

// Arguments: [boxes] [--no-sleep], in any order. Returns -1 on a bad argument.
int parse_args(int argc, char** argv, bool& sleeping) {
  int n = 1000;
  bool have_n = false;
  sleeping = true;
  for (int a = 1; a < argc; ++a) {
    if (std::strcmp(argv[a], "--no-sleep") == 0) {
      sleeping = false;
      continue;
    }
    if (have_n) return -1;
    char* end = nullptr;
    long v = std::strtol(argv[a], &end, 10);
    if (end == argv[a] || *end != '\0' || v <= 0 || v % 100 != 0 || v > 1000000) return -1;
    n = static_cast<int>(v);
    have_n = true;
  }
  return n;
}

}  // namespace

int main(int argc, char** argv) {
  bool sleeping = true;
  const int n = parse_args(argc, argv, sleeping);
  if (n < 0) {
    std::fprintf(stderr, "usage: %s [boxes] [--no-sleep]   (boxes: a positive multiple of 100, default 1000)\n",
                 argv[0]);
    return 2;
  }
  gDisableDeactivation = !sleeping;  // Bullet's global switch; false (sleeping on) is its default

  // World.
  auto config = std::make_unique<btDefaultCollisionConfiguration>();
  auto dispatcher = std::make_unique<btCollisionDispatcher>(config.get());
  auto broadphase = std::make_unique<btDbvtBroadphase>();
  auto solver = std::make_unique<btSequentialImpulseConstraintSolver>();
  auto world = std::make_unique<btDiscreteDynamicsWorld>(dispatcher.get(), broadphase.get(), solver.get(),
                                                         config.get());
  world->setGravity(btVector3(0, btScalar(-9.81), 0));
  world->getSolverInfo().m_numIterations = 10;

  // Ground: static plane y = 0.
  auto ground_shape = std::make_unique<btStaticPlaneShape>(btVector3(0, 1, 0), btScalar(0));
  btRigidBody::btRigidBodyConstructionInfo ground_info(0, nullptr, ground_shape.get());
  ground_info.m_friction = btScalar(kFriction);
  ground_info.m_restitution = 0;
  auto ground = std::make_unique<btRigidBody>(ground_info);
  world->addRigidBody(ground.get());

  // Boxes: one shared shape.
  const double half = kEdge / 2;
  const double mass = kDensity * kEdge * kEdge * kEdge;  // 125 kg
  auto box_shape = std::make_unique<btBoxShape>(btVector3(btScalar(half), btScalar(half), btScalar(half)));
  btVector3 inertia(0, 0, 0);
  box_shape->calculateLocalInertia(btScalar(mass), inertia);

  std::vector<std::unique_ptr<btRigidBody>> boxes;
  boxes.reserve(n);
  for (int i = 0; i < n; ++i) {
    const int ix = i % 10;       // x fastest
    const int iz = (i / 10) % 10;  // then z
    const int iy = i / 100;      // then y (layer)
    const double x = (ix - 4.5) * 0.75;
    const double z = (iz - 4.5) * 0.75;
    const double y = 0.3 + iy * 0.55;
    const double angle = 7.0 * ((i * 37) % 13) * kPi / 180.0;

    btRigidBody::btRigidBodyConstructionInfo info(btScalar(mass), nullptr, box_shape.get(), inertia);
    info.m_startWorldTransform.setIdentity();
    info.m_startWorldTransform.setOrigin(btVector3(btScalar(x), btScalar(y), btScalar(z)));
    info.m_startWorldTransform.setRotation(btQuaternion(btVector3(0, 1, 0), btScalar(angle)));
    info.m_friction = btScalar(kFriction);
    info.m_restitution = 0;
    info.m_linearDamping = 0;
    info.m_angularDamping = 0;
    boxes.push_back(std::make_unique<btRigidBody>(info));
    world->addRigidBody(boxes.back().get());
  }

  // Step: time only the stepSimulation calls.
  using clock = std::chrono::steady_clock;
  clock::duration stepping{0};
  double contact_sum = 0;
  for (int s = 0; s < kSteps; ++s) {
    const auto t0 = clock::now();
    world->stepSimulation(btScalar(kH), 0);
    stepping += clock::now() - t0;

    long contacts = 0;
    const int manifolds = dispatcher->getNumManifolds();
    for (int m = 0; m < manifolds; ++m) contacts += dispatcher->getManifoldByIndexInternal(m)->getNumContacts();
    contact_sum += static_cast<double>(contacts);
  }
  const double seconds = std::chrono::duration<double>(stepping).count();

  // Stability at the end.
  double max_speed = 0, height_sum = 0;
  int asleep = 0;
  for (const auto& b : boxes) {
    max_speed = std::max(max_speed, static_cast<double>(b->getLinearVelocity().length()));
    height_sum += b->getWorldTransform().getOrigin().y();
    if (b->getActivationState() == ISLAND_SLEEPING) ++asleep;
  }

  std::printf(
      "{\"name\": \"bullet_pile\", \"boxes\": %d, \"steps\": %d, \"h\": %.6f, \"seconds\": %.4f, "
      "\"steps_per_s\": %.1f, \"contacts_per_s\": %.4g, \"mean_contacts\": %.1f, \"final_max_speed\": %.4g, "
      "\"final_mean_height\": %.4f, \"asleep\": %d, \"sleeping_enabled\": %s}\n",
      n, kSteps, kH, seconds, kSteps / seconds, contact_sum / seconds, contact_sum / kSteps, max_speed,
      height_sum / n, asleep, sleeping ? "true" : "false");

  // Teardown: bodies out of the world before anything is destroyed.
  for (auto& b : boxes) world->removeRigidBody(b.get());
  world->removeRigidBody(ground.get());
  boxes.clear();
  ground.reset();
  world.reset();
  solver.reset();
  broadphase.reset();
  dispatcher.reset();
  config.reset();
  return 0;
}
