#!/usr/bin/env python3
"""Writes scenes/cloth_liquid.json: cloth and liquid acting on each other, four shots in one world,
the camera moving from one to the next (docs/cloth_liquid.md).

  0-6 s      water poured into a sheet held at its four corners: it sags, fills and overflows;
  6-12 s     a weaker sheet under a heavier pour tears, and the water pours through the tear;
  12-18 s    an absorbent flag dipped into a pool on its pole, lifted out darker, dripping;
  18-24 s    a towel pulled across a puddle soaks it up.
Run from the repository root: python3 scripts/make_cloth_liquid_scene.py
"""
import math

from make_rigid_scenes import film, write_scene

WATER = {"name": "water", "mass": 0.008, "alpha": 212.6, "beta": 0.085, "cutoff": 0.02725, "viscosity": 6,
         "color": [0.22, 0.5, 0.92]}


def r(x, n=4):
    return round(x, n)


def vec(*v):
    return [r(x) for x in v]


def posts(objects, x0, half, top, name, tilt):
    """Four wooden posts whose tops hold a sheet's corners (the sheet turned by `tilt` degrees about
    x: its +z edge lower)."""
    s, c = math.sin(math.radians(tilt)), math.cos(math.radians(tilt))
    for k, (sx, sz) in enumerate(((-1, -1), (1, -1), (-1, 1), (1, 1))):
        x, y, z = x0 + sx * (half + 0.025), top - sz * half * s, sz * (half * c + 0.025)
        objects.append({"type": "capsule", "name": "%s_post%d" % (name, k), "start": vec(x, 0.0, z),
                        "end": vec(x, y + 0.02, z), "radius": 0.025, "color": [0.45, 0.32, 0.2], "specular": 0.1})


def nozzle(objects, x, y, z, name):
    """A copper pipe coming in from above and behind, its mouth at (x, y, z)."""
    objects.append({"type": "capsule", "name": name, "start": vec(x, y + 0.03, z), "end": vec(x, y + 0.9, z - 0.9),
                    "radius": 0.035, "color": [0.72, 0.42, 0.25], "specular": 0.7, "shininess": 60})


def water(name, blocks=(), emitters=(), particles=None):
    # A lower surface level than the default (0.5) keeps a falling stream joined.
    w = {"type": "fluid", "name": name, "radius": 0.01, "draw": "surface", "surface_iso": 0.3, "species": [WATER],
         "blocks": list(blocks), "emitters": list(emitters), "transmission": 0.85, "absorption_depth": 0.1, "specular": 0.5, "roughness": 0.08}
    if particles:
        w["particles"] = [{"positions": particles}]
    return w


def puddle_points(cx, cz, radius, spacing, y):
    """A puddle's particles: a hexagonal layer `spacing` apart inside a rounded, uneven outline
    (radius varying by a fifth around it), each moved a little off the lattice (a fixed pattern)."""
    pts = []
    row = spacing * math.sqrt(3) / 2
    n = int(radius * 1.3 / row) + 1
    for j in range(-n, n + 1):
        for i in range(-n, n + 1):
            x = (i + 0.5 * (j % 2)) * spacing
            z = j * row
            a = math.atan2(z, x)
            edge = radius * (1 + 0.12 * math.sin(3 * a + 1.0) + 0.08 * math.sin(5 * a + 2.0))
            if math.hypot(x, z) > edge:
                continue
            k = i * 7919 + j * 104729
            dx, dz = 0.15 * spacing * math.sin(k * 0.7), 0.15 * spacing * math.cos(k * 1.3)
            pts.append([r(cx + x + dx), r(y), r(cz + z + dz)])
    return pts


def hammock(objects, bodies, x0, t0, name, tear, rate, stop, color, stiffness, tilt=0.0):
    half = 0.4
    posts(objects, x0, half, 1.0, name, tilt)
    cloth = {"type": "cloth", "name": name, "position": [x0, 1.0, 0], "rotation_deg": [tilt, 0, 0],
             "size": [2 * half, 2 * half],
             "resolution": [22, 22], "mass": 0.2, "stiffness": stiffness, "damping": 2, "shear_stiffness": 600,
             "bend_stiffness": 1, "node_damping": 0.01, "thickness": 0.006,
             "pinned": ["corner_00", "corner_10", "corner_01", "corner_11"], "surface": {"friction": 0.4},
             "color": color, "specular": 0.08}
    if tear:
        cloth["tear"] = {"strain": tear, "variation": 0.3}
    bodies.append(cloth)
    nozzle(objects, x0 + 0.05, 1.45, 0.0, name + "_pipe")
    # A stream as wide as the pipe (3.5 cm): its layers of 11 particles leave under 2 cm apart at
    # these rates, within the cutoff (5 cm layers of 19 left 3 cm apart, a string of discs: `reel
    # check` says so); it leaves just under the pipe's mouth.
    bodies.append(water(name + "_water", emitters=[{"position": vec(x0 + 0.05, 1.43, 0.0), "direction": [0, -1, 0],
                                                   "speed": 1.5, "radius": 0.035, "rate": rate, "start": t0, "stop": stop,
                                                   "nozzle": False}]))  # the copper pipe above is its nozzle


def flag(objects, bodies, x0):
    """A pool, and a flag on a pole lowered into it at 13 s and lifted out at 15 s."""
    objects.append({"type": "container", "name": "pool", "center": [x0, 0.12, 0], "size": [0.6, 0.24, 0.28],
                    "wall": 0.02, "color": [0.7, 0.74, 0.78], "opacity": 0.3, "specular": 0.6})
    bodies.append(water("pool_water", blocks=[{"min": [x0 - 0.28, 0.02, -0.12], "max": [x0 + 0.28, 0.18, 0.12],
                                               "spacing": 0.02, "jitter": 0.1}]))
    top = 1.15  # the pole's top at rest; the flag hangs from it, 0.5 m wide, 0.42 m tall
    keys = [(0.0, 0.0), (12.8, 0.0), (13.8, -0.74), (14.8, -0.74), (15.8, 0.0), (24.0, 0.0)]
    pole_a, pole_b = (x0 - 0.27, top - 0.75, 0.0), (x0 - 0.27, top + 0.05, 0.0)
    mid = [(pole_a[k] + pole_b[k]) / 2 for k in range(3)]
    objects.append({"type": "capsule", "name": "pole", "start": vec(*pole_a), "end": vec(*pole_b), "radius": 0.015,
                    "color": [0.3, 0.3, 0.32], "specular": 0.5,
                    "motion": {"keys": [{"time": t, "position": vec(mid[0], mid[1] + dy, mid[2])} for t, dy in keys]}})
    # The sheet in the x–z plane turned upright (x along the flag, z down the pole): its edge
    # z0 is at the top, x0 along the pole.
    bodies.append({"type": "cloth", "name": "flag", "position": [x0 - 0.02, top - 0.21, 0.0], "size": [0.5, 0.42],
                   "rotation_deg": [90, 0, 0], "resolution": [22, 19], "mass": 0.08, "stiffness": 1500,
                   "damping": 1, "shear_stiffness": 400, "bend_stiffness": 0.5, "node_damping": 0.004,
                   "thickness": 0.005, "absorbency": 0.9, "surface": {"friction": 0.3},
                   "grips": [{"nodes": ["edge_x0"], "keys": [{"time": t, "offset": [0, r(dy), 0]} for t, dy in keys]}],
                   "air": {"viscous": 0.3, "drag": 0.2}, "color": [0.85, 0.16, 0.12], "specular": 0.05})


def towel(objects, bodies, x0):
    """A towel on the floor pulled by a wooden bar across a puddle, 19-23 s."""
    keys = [(0.0, 0.0), (19.0, 0.0), (23.0, 1.05), (24.0, 1.05)]
    bar = (x0 - 0.18, 0.07, 0.0)
    objects.append({"type": "box", "name": "bar", "center": vec(*bar), "size": [0.05, 0.05, 0.5],
                    "color": [0.5, 0.36, 0.22], "specular": 0.1,
                    "motion": {"keys": [{"time": t, "position": vec(bar[0] + dx, bar[1], bar[2])} for t, dx in keys]}})
    bodies.append({"type": "cloth", "name": "towel", "position": [x0 - 0.39, 0.008, 0.0], "size": [0.42, 0.42],
                   "resolution": [18, 18], "mass": 0.4, "stiffness": 1200, "damping": 1, "shear_stiffness": 300,
                   "bend_stiffness": 0.3, "node_damping": 0.01, "thickness": 0.006, "absorbency": 1,
                   "surface": {"friction": 0.5},
                   "grips": [{"nodes": ["edge_x1"], "keys": [{"time": t, "offset": [r(dx), 0.03, 0]} for t, dx in keys]}],
                   "color": [0.3, 0.5, 0.78], "specular": 0.03})
    # A rounded puddle of about 200 particles (a square block of them read as a tile).
    bodies.append(water("puddle", particles=puddle_points(x0 + 0.19, 0.0, 0.15, 0.02, 0.013)))


def main():
    objects = [{"type": "plane", "name": "floor", "pattern": "wood", "tile": 2.0, "color": [1, 1, 1], "specular": 0.35, "roughness": 0.55,
                "surface": {"friction": 0.5}}]
    bodies = []
    # Its front edge 7 cm lower: filled, it overflows there.
    hammock(objects, bodies, 0.0, 0.3, "hammock", None, 900, 4.6, [0.9, 0.78, 0.55], 5000, tilt=10.0)
    hammock(objects, bodies, 4.0, 6.3, "sling", 0.2, 1000, 9.6, [0.55, 0.7, 0.85], 2500)
    flag(objects, bodies, 8.0)
    towel(objects, bodies, 12.0)
    # Four shots, cut between (the camera's keys are joined by Catmull–Rom: each shot's start and
    # end are held for half a frame, so the move inside a shot eases in and out and the cut falls
    # between two frames).
    shots = [(0.0, 6.0, ((0.65, 1.75, 1.55), (0.0, 1.15, 0.0)), ((-0.55, 1.7, 1.6), (0.0, 1.1, 0.0))),
             (6.0, 12.0, ((4.65, 1.7, 1.55), (4.0, 1.12, 0.0)), ((3.4, 1.25, 1.7), (4.0, 0.7, 0.0))),
             (12.0, 18.0, ((8.45, 1.0, 1.45), (8.0, 0.62, 0.0)), ((7.55, 0.95, 1.4), (8.0, 0.55, 0.0))),
             (18.0, 24.0, ((11.75, 0.75, 0.95), (11.85, 0.0, 0.0)), ((12.75, 0.7, 0.9), (12.75, 0.0, 0.0)))]
    cam = []
    for t0, t1, (p0, q0), (p1, q1) in shots:
        cam += [(t0, p0, q0), (r(t0 + 1 / 60), p0, q0), (r(t1 - 1 / 30), p1, q1), (r(t1 - 1 / 60), p1, q1)]
    # The look the films share (make_rigid_scenes.film: ACES, a sky, occlusion, a soft sun).
    scene = film("cloth_liquid", 24.0, 24, cam, objects, bodies, auto_substeps=True, integrator="implicit_euler",
                 implicit={"cg_tolerance": 1e-3}, seed=16, wind={"velocity": [1.2, 0, 0.4], "gust": 0.8})
    write_scene("scenes/cloth_liquid.json",
                "// Cloth and liquid acting on each other (made by scripts/make_cloth_liquid_scene.py): water\n"
                "// poured into a sheet held at its corners, a weaker one that tears under the load, an absorbent\n"
                "// flag dipped into a pool and lifted out dripping, a towel pulled across a puddle.\n"
                "// Docs: docs/cloth_liquid.md\n", scene)


if __name__ == "__main__":
    main()
