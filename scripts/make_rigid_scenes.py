#!/usr/bin/env python3
"""Writes scenes/rigid_bodies.json and scenes/cloth_and_crates.json.

scenes/rigid_bodies.json: three rigid-body shots in one world, the camera moving from
one to the next (every body's inertia comes from its shape; the bunny's from its mesh).

  0-6.5 s    a tower of 36 blocks knocked down by a swinging wrecking ball (keyed, kinematic);
  6.5-13 s   crates pushed off a landing tumble down a flight of stairs;
  13-20 s    a trapdoor slides away and a bunny (scenes/meshes/bunny.obj) and five dice fall,
             bounce and roll.
scenes/cloth_and_crates.json: rigid bodies coupled with cloth and a liquid:
  0-6 s      a sheet thrown over a pile of crates drapes over them;
  6-12 s     crates dropped one after another onto a trampoline cloth held at its corners;
  12-18 s    a crate drops through a trapdoor into a water tank, splashes and floats.
Run from the repository root: python3 scripts/make_rigid_scenes.py
"""
import json
import math

G = 9.81


def r(x, n=4):
    return round(x, n)


def vec(*v):
    return [r(x) for x in v]


def tower(bodies, x0):
    """12 layers of 3 blocks (0.75 × 0.15 × 0.25 m), each layer across the one below."""
    colors = [[0.85, 0.62, 0.35], [0.78, 0.52, 0.28], [0.9, 0.72, 0.45]]
    for layer in range(12):
        y = 0.075 + 0.15 * layer
        for k in range(3):
            off = (k - 1) * 0.255
            if layer % 2 == 0:  # long along x, side by side in z
                pos, rot = vec(x0, y, off), [0, 90, 0]
            else:               # long along z, side by side in x
                pos, rot = vec(x0 + off, y, 0), [0, 0, 0]
            bodies.append({"type": "rigid", "name": "block_%d_%d" % (layer, k), "shape": "box",
                           "size": [0.25, 0.15, 0.75], "density": 500, "position": pos, "rotation_deg": rot,
                           "surface": {"friction": 0.6}, "color": colors[(layer + k) % 3], "specular": 0.15})


def wrecking_ball(bodies, objects, x0):
    """A pendulum of length L from a beam 3.6 m up, let go at 65° at t = 1 s (keyed: it does not
    slow as it hits)."""
    L, pivot = 2.9, (x0, 3.6, 0.0)
    w = math.sqrt(G / L)
    th0 = math.radians(65)
    ball, rope = [], []
    for i in range(0, 131):
        t = i * 0.05
        th = -th0 if t < 1.0 else -th0 * math.cos(w * (t - 1.0)) * math.exp(-0.05 * (t - 1.0))
        bx, by = pivot[0] + L * math.sin(th), pivot[1] - L * math.cos(th)
        ball.append({"time": r(t, 3), "position": vec(bx, by, 0)})
        mx, my = pivot[0] + 0.5 * (L - 0.3) * math.sin(th), pivot[1] - 0.5 * (L - 0.3) * math.cos(th)
        rope.append({"time": r(t, 3), "position": vec(mx, my, 0), "rotation_deg": [0, 0, r(math.degrees(th), 3)]})
    bodies.append({"type": "rigid", "name": "wrecking_ball", "shape": "sphere", "radius": 0.3,
                   "position": ball[0]["position"], "motion": {"keys": ball}, "color": [0.18, 0.18, 0.2],
                   "specular": 0.7, "shininess": 60})
    objects.append({"type": "capsule", "name": "rope", "start": vec(pivot[0], pivot[1] - (L - 0.3), 0),
                    "end": vec(*pivot), "radius": 0.02, "color": [0.35, 0.3, 0.25],
                    "motion": {"keys": [dict(k, position=k["position"]) for k in rope]}})
    objects.append({"type": "box", "name": "beam", "center": vec(pivot[0], pivot[1] + 0.08, 0),
                    "size": [0.2, 0.16, 1.6], "color": [0.3, 0.3, 0.33]})
    for z in (-0.75, 0.75):
        objects.append({"type": "box", "name": "post%+d" % int(z * 4), "center": vec(pivot[0], 1.84, z),
                        "size": [0.16, 3.68, 0.16], "color": [0.3, 0.3, 0.33]})


def stairs(bodies, objects, x0):
    """Seven steps down toward +x (0.3 m rise, 0.45 m run), a landing on top with four crates, and a
    keyed pusher that sweeps them off at t = 7.5 s."""
    steps = 7
    for k in range(steps):
        h = 0.3 * (steps - k)
        objects.append({"type": "box", "name": "step%d" % k, "center": vec(x0 + 0.45 * k, h / 2, 0),
                        "size": [0.45, r(h), 2.4], "color": [0.62, 0.6, 0.58], "surface": {"friction": 0.35}})
    top = 0.3 * steps
    objects.append({"type": "box", "name": "landing", "center": vec(x0 - 0.9, top / 2, 0), "size": [1.4, r(top), 2.4],
                    "color": [0.62, 0.6, 0.58], "surface": {"friction": 0.5}})
    colors = [[0.72, 0.45, 0.2], [0.6, 0.38, 0.18], [0.8, 0.55, 0.3], [0.66, 0.42, 0.22]]
    for k, z in enumerate((-0.75, -0.25, 0.25, 0.75)):
        bodies.append({"type": "rigid", "name": "crate%d" % k, "shape": "box", "size": [0.4, 0.4, 0.4], "density": 250,
                       "position": vec(x0 - 0.6 + 0.1 * (k % 2), top + 0.2, z), "rotation_deg": [0, 8 * k - 12, 0],
                       "surface": {"friction": 0.3, "restitution": 0.2}, "color": colors[k], "specular": 0.1})
    start = vec(x0 - 1.45, top + 0.25, 0)
    bodies.append({"type": "rigid", "name": "pusher", "shape": "box", "size": [0.12, 0.4, 2.2], "position": start,
                   "color": [0.25, 0.35, 0.6],
                   "motion": {"keys": [{"time": 0, "position": start}, {"time": 7.4, "position": start},
                                       {"time": 8.1, "position": vec(x0 + 0.1, top + 0.25, 0)},
                                       {"time": 9.4, "position": start}]}})


def drop(bodies, objects, x0):
    """A bunny and five dice on a trapdoor 1.6 m up that slides away at t = 13.6 s."""
    y = 1.6
    door = vec(x0, y - 0.05, 0)
    bodies.append({"type": "rigid", "name": "trapdoor", "shape": "box", "size": [1.6, 0.1, 1.4], "position": door,
                   "color": [0.4, 0.3, 0.22],
                   "motion": {"keys": [{"time": 0, "position": door}, {"time": 13.6, "position": door},
                                       {"time": 14.0, "position": vec(x0, y - 0.05, -1.6)}]}})
    bodies.append({"type": "rigid", "name": "bunny", "shape": "mesh", "file": "meshes/bunny.obj", "scale": 1.2,
                   "position": vec(x0 - 0.3, y + 0.25, 0.1), "rotation_deg": [0, -30, 0], "density": 400,
                   "surface": {"friction": 0.5, "restitution": 0.35}, "color": [0.92, 0.9, 0.86], "specular": 0.2})
    dice = [(0.35, -0.35, [0.85, 0.1, 0.1]), (0.5, 0.1, [0.95, 0.95, 0.92]), (0.2, 0.4, [0.1, 0.35, 0.8]),
            (0.6, -0.05, [0.95, 0.75, 0.1]), (0.05, -0.15, [0.15, 0.6, 0.25])]
    for k, (dx, dz, col) in enumerate(dice):
        bodies.append({"type": "rigid", "name": "die%d" % k, "shape": "box", "size": [0.12, 0.12, 0.12], "density": 1200,
                       "position": vec(x0 + dx, y + 0.06 + 0.13 * (k % 2), dz), "rotation_deg": [17 * k, 29 * k, 11 * k],
                       "surface": {"friction": 0.4, "restitution": 0.5}, "color": col, "specular": 0.5, "shininess": 50})


def crate(name, size, pos, color, density=150, rot=(0, 0, 0), **extra):
    b = {"type": "rigid", "name": name, "shape": "box", "size": [size] * 3, "density": density,
         "position": vec(*pos), "rotation_deg": list(rot), "surface": {"friction": 0.5, "restitution": 0.1},
         "color": color, "specular": 0.1}
    b.update(extra)
    return b


def cloth_and_crates():
    woods = [[0.72, 0.45, 0.2], [0.6, 0.38, 0.18], [0.8, 0.55, 0.3], [0.66, 0.42, 0.22], [0.76, 0.5, 0.26]]
    objects = [{"type": "plane", "name": "floor", "pattern": "concrete", "color": [1, 1, 1],
                "surface": {"friction": 0.6}}]
    bodies = []
    # The trampoline: a 1.6 m sheet held at its corners 1 m up (posts drawn under them), and three
    # crates dropped onto it one after another from 2.2 m.
    bodies.append({"type": "cloth", "name": "trampoline", "position": [0, 1.0, 0], "size": [1.6, 1.6],
                   "resolution": [24, 24], "mass": 1.2, "stiffness": 4000, "damping": 0.5, "shear_stiffness": 1000,
                   "bend_stiffness": 5, "node_damping": 0.05, "thickness": 0.01,
                   "pinned": ["corner_00", "corner_10", "corner_01", "corner_11"],
                   "color": [0.15, 0.2, 0.35], "specular": 0.1})
    for k, (x, z) in enumerate([(-0.8, -0.8), (0.8, -0.8), (-0.8, 0.8), (0.8, 0.8)]):
        objects.append({"type": "capsule", "name": "post%d" % k, "start": [x, 0, z], "end": [x, 0.98, z], "radius": 0.03,
                        "color": [0.3, 0.3, 0.33]})
    for k, (t, x, z) in enumerate([(6.4, 0.0, 0.0), (7.6, 0.25, -0.2), (8.8, -0.25, 0.15)]):
        # Each crate waits on a small keyed shelf that slides away at its time.
        y = 2.2
        bodies.append(crate("drop%d" % k, 0.28, (x, y + 0.14, z), woods[k], rot=(0, 20 * k, 0)))
        shelf = vec(x, y - 0.02, z)
        bodies.append({"type": "rigid", "name": "shelf%d" % k, "shape": "box", "size": [0.34, 0.04, 0.34],
                       "position": shelf, "color": [0.3, 0.3, 0.33],
                       "motion": {"keys": [{"time": 0, "position": shelf}, {"time": t, "position": shelf},
                                           {"time": t + 0.25, "position": vec(x + 0.5, y - 0.02, z)}]}})
    # The pile: six crates in a 3-2-1 pyramid; a sheet thrown over it from the left.
    x0 = 6.0
    k = 0
    for row, n in enumerate((3, 2, 1)):
        for i in range(n):
            x = x0 + (i - (n - 1) / 2) * 0.42
            bodies.append(crate("pile%d" % k, 0.4, (x, 0.2 + 0.4 * row, 0), woods[k % 5], density=200,
                                rot=(0, 6 * (k % 3) - 6, 0)))
            k += 1
    bodies.append({"type": "cloth", "name": "sheet", "position": [x0 - 1.6, 2.3, 0], "size": [2.2, 2.0],
                   "resolution": [36, 33], "mass": 0.6, "velocity": [1.3, 0.4, 0],
                   "stiffness": 3000, "damping": 0.4, "shear_stiffness": 800, "bend_stiffness": 2,
                   "node_damping": 0.001, "thickness": 0.012, "self_collision": True, "strain_limit": 0.05,
                   "air": {"viscous": 1.0, "drag": 0.2, "lift": 0.4}, "pattern": "rug", "specular": 0.05})
    # The tank: water 0.16 m deep; a crate on a trapdoor above it.
    x1 = 12.0
    objects.append({"type": "container", "name": "tank", "center": [x1, 0.15, 0], "size": [0.9, 0.3, 0.56],
                    "wall": 0.02, "color": [0.75, 0.78, 0.8], "opacity": 0.35, "specular": 0.6})
    bodies.append({"type": "fluid", "name": "water", "radius": 0.01, "draw": "surface",
                   "species": [{"name": "water", "mass": 0.008, "alpha": 212.6, "beta": 0.085, "cutoff": 0.02725,
                                "viscosity": 4, "color": [0.2, 0.5, 0.9]}],
                   "blocks": [{"min": [x1 - 0.43, 0.03, -0.25], "max": [x1 + 0.43, 0.17, 0.25], "spacing": 0.02,
                               "jitter": 0.1}],
                   "specular": 0.8, "shininess": 90})
    bodies.append(crate("floater", 0.16, (x1 - 0.1, 0.62, 0), [0.8, 0.55, 0.3], density=450, rot=(0, 25, 10)))
    door = vec(x1 - 0.1, 0.52, 0)
    bodies.append({"type": "rigid", "name": "trapdoor", "shape": "box", "size": [0.26, 0.03, 0.26], "position": door,
                   "color": [0.3, 0.3, 0.33],
                   "motion": {"keys": [{"time": 0, "position": door}, {"time": 13.0, "position": door},
                                       {"time": 13.25, "position": vec(x1 - 0.1, 0.52, -0.35)}]}})
    cam = [(0.0, (x0 - 1.4, 2.1, 3.5), (x0 - 0.5, 0.8, 0.0)), (5.6, (x0 + 0.4, 2.0, 3.2), (x0 - 0.3, 0.5, 0.0)),
           (6.2, (1.6, 1.6, 2.7), (0.0, 1.55, 0.0)), (9.0, (1.6, 1.75, 2.6), (0.0, 1.05, 0.0)),
           (11.6, (1.3, 1.6, 2.4), (-0.2, 0.8, 0.0)),
           (12.2, (x1 - 0.3, 0.95, 1.25), (x1, 0.2, 0.0)), (18.0, (x1 + 0.35, 0.85, 1.15), (x1, 0.15, 0.0))]
    return film("cloth_and_crates", 18.0, 24, cam, objects, bodies, auto_substeps=True, integrator="implicit_euler",
                seed=5)


def film(name, duration, substeps, cam, objects, bodies, **extra):
    """A 1280x720 film of the films' common look: ACES, a sky lighting the scene, ambient occlusion,
    fog to the horizon, a sun with soft shadows (docs/rendering.md)."""
    scene = {"format": "reel/1", "name": name, "duration": duration, "fps": 30, "substeps": substeps}
    scene.update(extra)
    scene.update({
        "gravity": [0, -G, 0],
        "render": {"width": 1280, "height": 720, "samples": 4,
                   "background": {"top": [0.3, 0.42, 0.62], "bottom": [0.86, 0.84, 0.8]},
                   "tonemap": "aces", "exposure": -0.3, "environment": {"sky": True, "intensity": 0.7},
                   "ao": {"radius": 0.4}, "fog": {"color": [0.86, 0.84, 0.8], "density": 0.015}},
        "camera": {"position": list(cam[0][1]), "target": list(cam[0][2]), "fov_deg": 45,
                   "keys": [{"time": t, "position": list(p), "target": list(q)} for t, p, q in cam]},
        "lights": [{"type": "directional", "direction": [-0.45, -1.0, -0.35], "color": [1.0, 0.96, 0.9],
                    "intensity": 1.5, "shadows": True, "angle_deg": 2.5}],
        "objects": objects,
        "bodies": bodies,
    })
    return scene


def write_scene(path, header, scene):
    """Writes a scene file: its // header lines, then the JSON."""
    with open(path, "w") as f:
        f.write(header)
        json.dump(scene, f, indent=1)
        f.write("\n")


def main():
    bodies, objects = [], [{"type": "plane", "name": "floor", "pattern": "concrete", "color": [1, 1, 1],
                            "surface": {"friction": 0.6, "restitution": 0.2}}]
    tower(bodies, 0.0)
    wrecking_ball(bodies, objects, 0.0)
    stairs(bodies, objects, 7.0)
    drop(bodies, objects, 14.0)
    cam = [(0.0, (-2.6, 2.1, 4.3), (0.0, 1.2, 0.0)), (6.0, (-1.6, 1.7, 4.3), (0.4, 0.5, 0.0)),
           (7.0, (5.6, 3.2, 5.6), (7.6, 1.2, 0.0)), (12.5, (8.6, 2.4, 5.4), (9.6, 0.6, 0.0)),
           (13.3, (13.4, 1.9, 3.2), (13.9, 1.0, 0.0)), (20.0, (14.3, 1.3, 2.9), (13.3, 0.25, 0.3))]
    scene = film("rigid_bodies", 20.0, 8, cam, objects, bodies, seed=7)
    write_scene("scenes/rigid_bodies.json",
                "// Rigid bodies (made by scripts/make_rigid_scenes.py): a tower of blocks knocked down by a\n"
                "// swinging wrecking ball, crates tumbling down stairs, a bunny mesh and dice bouncing; each\n"
                "// body's inertia comes from its shape (the bunny's from its mesh, Mirtich 1996).\n"
                "// Docs: docs/rigid.md\n", scene)
    write_scene("scenes/cloth_and_crates.json",
                "// Rigid bodies with cloth and a liquid (made by scripts/make_rigid_scenes.py): a sheet thrown over\n"
                "// a pile of crates, crates dropped onto a trampoline cloth held at its corners, a crate dropped\n"
                "// into a water tank that splashes and floats. Momentum passes both ways through the coupling stage.\n"
                "// Docs: docs/rigid.md\n", cloth_and_crates())


if __name__ == "__main__":
    main()
