#!/usr/bin/env python3
"""Writes scenes/rigid_bodies.json: three rigid-body shots in one world, the camera moving from
one to the next (every body's inertia comes from its shape; the bunny's from its mesh).

  0-6.5 s    a tower of 36 blocks knocked down by a swinging wrecking ball (keyed, kinematic);
  6.5-13 s   crates pushed off a landing tumble down a flight of stairs;
  13-20 s    a trapdoor slides away and a bunny (scenes/meshes/bunny.obj) and five dice fall,
             bounce and roll.
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
            if layer % 2 == 0:
                pos, rot = vec(x0 + off, y, 0), [0, 90, 0]
            else:
                pos, rot = vec(x0, y, off), [0, 0, 0]
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
                        "size": [0.45, r(h), 2.4], "color": [0.62, 0.6, 0.58], "surface": {"friction": 0.5}})
    top = 0.3 * steps
    objects.append({"type": "box", "name": "landing", "center": vec(x0 - 0.9, top / 2, 0), "size": [1.4, r(top), 2.4],
                    "color": [0.62, 0.6, 0.58], "surface": {"friction": 0.5}})
    colors = [[0.72, 0.45, 0.2], [0.6, 0.38, 0.18], [0.8, 0.55, 0.3], [0.66, 0.42, 0.22]]
    for k, z in enumerate((-0.75, -0.25, 0.25, 0.75)):
        bodies.append({"type": "rigid", "name": "crate%d" % k, "shape": "box", "size": [0.4, 0.4, 0.4], "density": 250,
                       "position": vec(x0 - 0.6 + 0.1 * (k % 2), top + 0.2, z), "rotation_deg": [0, 8 * k - 12, 0],
                       "surface": {"friction": 0.45, "restitution": 0.15}, "color": colors[k], "specular": 0.1})
    start = vec(x0 - 1.45, top + 0.25, 0)
    bodies.append({"type": "rigid", "name": "pusher", "shape": "box", "size": [0.12, 0.4, 2.2], "position": start,
                   "color": [0.25, 0.35, 0.6],
                   "motion": {"keys": [{"time": 0, "position": start}, {"time": 7.4, "position": start},
                                       {"time": 8.4, "position": vec(x0 - 0.2, top + 0.25, 0)},
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


def main():
    bodies, objects = [], [{"type": "plane", "name": "floor", "checker": True, "color": [0.74, 0.72, 0.68],
                            "surface": {"friction": 0.6, "restitution": 0.2}}]
    tower(bodies, 0.0)
    wrecking_ball(bodies, objects, 0.0)
    stairs(bodies, objects, 7.0)
    drop(bodies, objects, 14.0)
    cam = [(0.0, (-3.2, 2.4, 5.2), (0.0, 1.2, 0.0)), (6.0, (-1.8, 1.9, 5.0), (0.3, 0.5, 0.0)),
           (7.0, (5.2, 3.2, 5.6), (7.3, 1.2, 0.0)), (12.5, (7.6, 2.4, 5.2), (8.6, 0.6, 0.0)),
           (13.3, (12.6, 1.8, 3.9), (14.2, 0.8, 0.0)), (20.0, (15.4, 1.4, 3.6), (14.4, 0.3, 0.0))]
    scene = {
        "format": "reel/1", "name": "rigid_bodies", "duration": 20.0, "fps": 30, "substeps": 8, "seed": 7,
        "gravity": [0, -G, 0],
        "render": {"width": 1280, "height": 720, "samples": 4,
                   "background": {"top": [0.3, 0.42, 0.62], "bottom": [0.86, 0.84, 0.8]}},
        "camera": {"position": list(cam[0][1]), "target": list(cam[0][2]), "fov_deg": 45,
                   "keys": [{"time": t, "position": list(p), "target": list(q)} for t, p, q in cam]},
        "lights": [{"type": "directional", "direction": [-0.45, -1.0, -0.35], "color": [1.0, 0.96, 0.9],
                    "intensity": 1.15, "shadows": True},
                   {"type": "ambient", "color": [0.55, 0.62, 0.75], "intensity": 0.5}],
        "objects": objects,
        "bodies": bodies,
    }
    with open("scenes/rigid_bodies.json", "w") as f:
        f.write("// Rigid bodies (made by scripts/make_rigid_scenes.py): a tower of blocks knocked down by a\n"
                "// swinging wrecking ball, crates tumbling down stairs, a bunny mesh and dice bouncing; each\n"
                "// body's inertia comes from its shape (the bunny's from its mesh, Mirtich 1996).\n"
                "// Docs: docs/rigid.md\n")
        json.dump(scene, f, indent=1)
        f.write("\n")


if __name__ == "__main__":
    main()
