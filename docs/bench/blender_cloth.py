# Headless Blender cloth benchmark, for comparison with `reel bench cloth`.
#
# Run:
#   blender -b --factory-startup --python docs/bench/blender_cloth.py -- \
#       --size 64 --self-collision 0 --seconds 2
#
# Scene: a 2 m x 2 m sheet of exactly N x N vertices (N = --size), horizontal
# at z = 1.5 m, centred above a UV sphere (radius 0.5 m, at the origin) that is
# a collision object. The sheet gets a Cloth modifier with cotton-like settings
# (quality 5 steps/frame, Blender's default); self-collision is on or off per
# --self-collision. Scene runs at 30 fps.
#
# Measured: wall time (time.perf_counter) of stepping frames 2..last with
# scene.frame_set(f): the cloth solve into the in-memory point cache plus
# Blender's per-frame depsgraph evaluation. Setup and frame 1 are not timed.
# Prints a "drape:" line (evaluated sheet min/max z at the last frame, a sanity
# check) and one JSON line. In Blender 3.4 primitive_grid_add's subdivisions
# are cuts (s gives (s+1)^2 vertices, checked), so we pass N-1 to get N*N.
# --obj PATH writes the sheet at the last frame as an OBJ (y up), for reel to render beside
# its own drape (docs/cloth.md).
# Caveat: at N=64 (edge 3.2 cm) Blender's default self distance 0.015 makes the
# flat sheet "self-collide" and fall slowly; --self-distance 0.01 avoids it.
import argparse
import json
import os
import sys
import time

import bpy

FPS = 30


def parse_args():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    p = argparse.ArgumentParser(prog="blender_cloth.py")
    p.add_argument("--size", type=int, default=64, help="vertices per side")
    p.add_argument("--self-collision", type=int, default=0, choices=(0, 1))
    p.add_argument("--seconds", type=float, default=2.0, help="simulated seconds")
    p.add_argument("--self-distance", type=float, default=None,
                   help="self-collision distance (Blender default 0.015)")
    p.add_argument("--obj", default=None,
                   help="write the sheet at the last frame here as a Wavefront OBJ, y up (reel's axes)")
    return p.parse_args(argv)


def build_scene(n, self_collision, steps, self_distance=None):
    # Clear the default scene (cube, camera, light) and orphan meshes.
    bpy.ops.object.select_all(action="SELECT")
    bpy.ops.object.delete()
    for mesh in list(bpy.data.meshes):
        bpy.data.meshes.remove(mesh)

    scene = bpy.context.scene
    scene.render.fps = FPS
    scene.render.fps_base = 1.0
    scene.frame_start = 1
    scene.frame_end = 1 + steps

    # Collision sphere at the origin.
    bpy.ops.mesh.primitive_uv_sphere_add(radius=0.5, location=(0.0, 0.0, 0.0))
    sphere = bpy.context.object
    sphere.name = "Sphere"
    sphere.modifiers.new("Collision", "COLLISION")

    # Sheet: N-1 cuts per side -> N x N vertices, 2 m wide, at z = 1.5.
    bpy.ops.mesh.primitive_grid_add(x_subdivisions=n - 1, y_subdivisions=n - 1,
                                    size=2.0, location=(0.0, 0.0, 1.5))
    sheet = bpy.context.object
    sheet.name = "Sheet"
    cloth = sheet.modifiers.new("Cloth", "CLOTH")
    s = cloth.settings
    # Blender's "Cotton" preset values (quality 5 is also the default).
    s.quality = 5
    s.mass = 0.3
    s.air_damping = 1.0
    s.tension_stiffness = s.compression_stiffness = 15.0
    s.shear_stiffness = 15.0
    s.bending_stiffness = 0.5
    s.tension_damping = s.compression_damping = s.shear_damping = 5.0
    s.bending_damping = 0.5
    c = cloth.collision_settings
    c.use_collision = True
    c.use_self_collision = bool(self_collision)
    if self_distance is not None:
        c.self_distance_min = self_distance
    cache = cloth.point_cache
    cache.frame_start = scene.frame_start
    cache.frame_end = scene.frame_end
    return scene, sheet


def sheet_z_range(sheet):
    depsgraph = bpy.context.evaluated_depsgraph_get()
    ev = sheet.evaluated_get(depsgraph)
    mw = ev.matrix_world
    zs = [(mw @ v.co).z for v in ev.data.vertices]
    return min(zs), max(zs)


def write_obj(sheet, path):
    # The evaluated sheet in world space, Blender's z-up turned to reel's y-up: (x, z, -y).
    depsgraph = bpy.context.evaluated_depsgraph_get()
    ev = sheet.evaluated_get(depsgraph)
    mw = ev.matrix_world
    with open(path, "w") as f:
        f.write("# Blender %s cloth, last frame\n" % bpy.app.version_string)
        for v in ev.data.vertices:
            w = mw @ v.co
            f.write("v %.6f %.6f %.6f\n" % (w.x, w.z, -w.y))
        for poly in ev.data.polygons:
            f.write("f %s\n" % " ".join(str(i + 1) for i in poly.vertices))


def main():
    args = parse_args()
    n = args.size
    steps = max(1, round(args.seconds * FPS))
    scene, sheet = build_scene(n, args.self_collision, steps, args.self_distance)
    nverts = len(sheet.data.vertices)
    assert nverts == n * n, (nverts, n)

    scene.frame_set(scene.frame_start)  # reset cache / initial state, untimed
    t0 = time.perf_counter()
    for f in range(scene.frame_start + 1, scene.frame_end + 1):
        scene.frame_set(f)
    wall = time.perf_counter() - t0

    zmin, zmax = sheet_z_range(sheet)
    if args.obj:
        write_obj(sheet, args.obj)
    simulated = steps / FPS
    coll = sheet.modifiers["Cloth"].collision_settings
    print("drape: frame %d sheet z min %.4f max %.4f" % (scene.frame_current, zmin, zmax))
    print(json.dumps({
        "name": "blender_cloth",
        "blender": bpy.app.version_string,
        "grid": n,
        "vertices": nverts,
        "self_collision": bool(args.self_collision),
        "quality_steps": sheet.modifiers["Cloth"].settings.quality,
        "collision_distance": round(coll.distance_min, 4),
        "self_distance": round(coll.self_distance_min, 4),
        "fps": FPS,
        "frames": steps,
        "simulated_s": simulated,
        "wall_s": round(wall, 4),
        "wall_per_simulated_s": round(wall / simulated, 4),
        "threads": scene.render.threads,
        "cpu_count": os.cpu_count(),
    }))


main()
