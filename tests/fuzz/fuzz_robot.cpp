// libFuzzer target: a robot file (URDF or MJCF, picked by the first byte) loaded by an articulated
// body of a fixed scene, through the scene loader: the XML parser, the URDF or MJCF reader (links,
// joints, inertias, MJCF defaults and classes), the meshes it names (a small cube beside it; no
// other file may be read) and the figure's checks. A refusal (BadInput) is the expected answer.
#include <cstddef>
#include <cstdint>
#include <string>

#include "app/body_kinds.h"
#include "fuzz_files.h"

namespace {

const char* const kFiles[] = {"robot.urdf", "robot.xml"};

const char* const kCube =
    "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
    "f 1 4 3\nf 1 3 2\nf 5 6 7\nf 5 7 8\nf 1 2 6\nf 1 6 5\nf 2 3 7\nf 2 7 6\nf 3 4 8\nf 3 8 7\nf 4 1 5\nf 4 5 8\n";

const char* const kUrdf = R"(<?xml version="1.0"?>
<robot name="arm">
  <link name="base">
    <inertial><mass value="4"/><inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/></inertial>
    <collision><geometry><box size="0.3 0.3 0.1"/></geometry></collision>
  </link>
  <link name="upper">
    <inertial><origin xyz="0 0 0.2" rpy="0 0 0"/><mass value="1.5"/><inertia ixx="0.02" iyy="0.02" izz="0.002"/></inertial>
    <collision><origin xyz="0 0 0.2"/><geometry><cylinder radius="0.05" length="0.4"/></geometry></collision>
  </link>
  <link name="hand">
    <collision><geometry><mesh filename="parts/cube.obj" scale="0.1 0.1 0.1"/></geometry></collision>
    <visual><geometry><sphere radius="0.05"/></geometry><material name="m"><color rgba="1 0 0 1"/></material></visual>
  </link>
  <joint name="shoulder" type="revolute">
    <parent link="base"/><child link="upper"/><origin xyz="0 0 0.05" rpy="0 1.57 0"/>
    <axis xyz="0 1 0"/><limit lower="-2" upper="2" effort="50" velocity="3"/><dynamics damping="0.1"/>
  </joint>
  <joint name="wrist" type="prismatic">
    <parent link="upper"/><child link="hand"/><origin xyz="0 0 0.4"/><axis xyz="0 0 1"/><limit lower="0" upper="0.1"/>
  </joint>
</robot>
)";

const char* const kMjcf = R"(<mujoco model="chain">
  <compiler angle="degree" meshdir="parts"/>
  <option timestep="0.002" gravity="0 0 -9.81"/>
  <default>
    <geom density="800"/>
    <default class="limb"><joint range="-90 90" damping="0.1" axis="0 1 0"/><geom type="capsule" size="0.04"/></default>
  </default>
  <asset><mesh name="block" file="cube.obj" scale="0.2 0.1 0.3"/></asset>
  <worldbody>
    <geom type="plane" size="2 2 0.1"/>
    <body name="base" pos="0 0 1.5" euler="0 0 30">
      <freejoint/>
      <geom type="mesh" mesh="block"/>
      <body name="upper" childclass="limb" quat="1 0 0 0">
        <joint name="j1"/>
        <geom fromto="0 0 0 0.4 0 0"/>
        <body name="lower" pos="0.4 0 0">
          <joint name="j2" type="ball"/>
          <geom type="box" pos="0 0 -0.2" size="0.03 0.03 0.2" mass="0.5"/>
          <geom type="ellipsoid" size="0.05 0.04 0.03" pos="0 0 -0.4"/>
        </body>
      </body>
    </body>
  </worldbody>
  <actuator><motor joint="j1" gear="2"/></actuator>
</mujoco>
)";

std::string scenePath(int kind) {
  using namespace reel::fuzz;
  static const bool made = [] {
    put("scene_urdf.json", R"({"format": "reel/1", "duration": 1, "bodies": [{"type": "articulated", "urdf": "robot.urdf"}]})");
    put("scene_mjcf.json", R"({"format": "reel/1", "duration": 1, "bodies": [{"type": "articulated", "mjcf": "robot.xml"}]})");
    const std::string parts = privateDir() + "/parts";
    if (mkdir(parts.c_str(), 0700) != 0) std::abort();
    put("parts/cube.obj", kCube);
    put("cube.obj", kCube);
    return true;
  }();
  (void)made;
  return reel::fuzz::privateDir() + (kind == 0 ? "/scene_urdf.json" : "/scene_mjcf.json");
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  if (reel::fuzz::seedDir()) {
    reel::fuzz::seed("arm.urdf", 0, kUrdf);
    reel::fuzz::seed("chain.xml", 1, kMjcf);
    std::exit(0);
  }
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  const int kind = data[0] % 2;
  const std::string scene = scenePath(kind);
  reel::fuzz::put(kFiles[kind], std::string_view(reinterpret_cast<const char*>(data + 1), size - 1));
  const std::string text = reel::fuzz::slurp(scene);
  (void)reel::app::parseScene(text, scene);
  return 0;
}
