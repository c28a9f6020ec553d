#!/usr/bin/env python3
"""Writes the meshes the demo scenes import (reel makes its own assets; none is downloaded).

scenes/meshes/urn.obj: a closed surface of revolution (an urn on a foot, 0.9 m tall, unit
scale in metres), counter-clockwise faces seen from outside, with smooth normals left to
the importer.
scenes/meshes/bowl.obj: a thick-walled bowl (a closed solid of revolution: outer wall, rounded
rim, inner wall, flat bottom inside and out), 0.8 m across and 0.3 m tall.
scenes/meshes/bunny.obj: a rabbit-like solid for the rigid-body film (a star-shaped surface around
its centre: an egg of a body with Gaussian bumps for the head, two long ears, a tail and feet),
facing +x, 0.5 m long; closed, outward, never crossing itself (its inertia comes from the mesh).
Run from the repository root: python3 scripts/make_meshes.py
"""
import math
import os

# Profile (radius, height) from the foot to the lip, metres.
PROFILE = [(0.0, 0.0), (0.22, 0.0), (0.22, 0.04), (0.12, 0.08), (0.10, 0.14), (0.16, 0.22),
           (0.26, 0.34), (0.30, 0.46), (0.28, 0.58), (0.20, 0.70), (0.13, 0.78), (0.12, 0.84),
           (0.17, 0.88), (0.18, 0.90), (0.0, 0.90)]
SEGMENTS = 32


# The bowl's closed profile, going up the outside, over the rim and down the inside to the axis.
BOWL = [(0.0, 0.0), (0.22, 0.0), (0.30, 0.03), (0.36, 0.10), (0.39, 0.20), (0.40, 0.28),
        (0.395, 0.30), (0.37, 0.30), (0.355, 0.22), (0.32, 0.12), (0.26, 0.06), (0.18, 0.04),
        (0.0, 0.04)]


def revolve(profile):
    verts, faces = [], []
    rings = []
    for r, y in profile:
        if r == 0.0:  # a pole: one vertex
            rings.append([len(verts)])
            verts.append((0.0, y, 0.0))
            continue
        ring = []
        for s in range(SEGMENTS):
            a = 2 * math.pi * s / SEGMENTS
            ring.append(len(verts))
            verts.append((r * math.cos(a), y, -r * math.sin(a)))
        rings.append(ring)
    for lo, hi in zip(rings, rings[1:]):
        for s in range(SEGMENTS):
            t = (s + 1) % SEGMENTS
            if len(lo) == 1:      # bottom cap: fan seen from below
                faces.append((lo[0], hi[t], hi[s]))
            elif len(hi) == 1:    # top cap: fan seen from above
                faces.append((lo[s], lo[t], hi[0]))
            else:
                faces.append((lo[s], lo[t], hi[t]))
                faces.append((lo[s], hi[t], hi[s]))
    return verts, faces


# The bunny's bumps: (direction, height in m, angular width in rad).
BUNNY_BUMPS = [((0.75, 0.65, 0.0), 0.16, 0.42),    # head
               ((0.35, 1.0, 0.2), 0.30, 0.13),     # ears
               ((0.35, 1.0, -0.2), 0.30, 0.13),
               ((-1.0, 0.25, 0.0), 0.07, 0.28),    # tail
               ((0.55, -1.0, 0.45), 0.04, 0.3),    # feet
               ((0.55, -1.0, -0.45), 0.04, 0.3),
               ((-0.5, -1.0, 0.5), 0.05, 0.35),
               ((-0.5, -1.0, -0.5), 0.05, 0.35)]
BUNNY_BODY = (0.25, 0.17, 0.16)  # semi-axes of the egg, m


def bunny(rings=48, segments=64):
    """A star-shaped surface r(d) on a latitude grid with one vertex at each pole."""
    bumps = []
    for (x, y, z), h, w in BUNNY_BUMPS:
        n = math.sqrt(x * x + y * y + z * z)
        bumps.append(((x / n, y / n, z / n), h, w))

    def radius(d):
        ax, ay, az = BUNNY_BODY
        r = 1.0 / math.sqrt((d[0] / ax) ** 2 + (d[1] / ay) ** 2 + (d[2] / az) ** 2)
        for c, h, w in bumps:
            ang = math.acos(max(-1.0, min(1.0, d[0] * c[0] + d[1] * c[1] + d[2] * c[2])))
            r += h * math.exp(-(ang / w) ** 2)
        return r

    verts, faces = [(0.0, -radius((0.0, -1.0, 0.0)), 0.0)], []
    for j in range(1, rings):
        th = math.pi * j / rings  # from the south pole
        for s in range(segments):
            ph = 2 * math.pi * s / segments
            d = (math.sin(th) * math.cos(ph), -math.cos(th), -math.sin(th) * math.sin(ph))
            r = radius(d)
            verts.append((r * d[0], r * d[1], r * d[2]))
    verts.append((0.0, radius((0.0, 1.0, 0.0)), 0.0))
    top = len(verts) - 1

    def ring(j, s):
        return 1 + (j - 1) * segments + s % segments

    for s in range(segments):
        faces.append((0, ring(1, s + 1), ring(1, s)))
        faces.append((ring(rings - 1, s), ring(rings - 1, s + 1), top))
    for j in range(1, rings - 1):
        for s in range(segments):
            faces.append((ring(j, s), ring(j, s + 1), ring(j + 1, s + 1)))
            faces.append((ring(j, s), ring(j + 1, s + 1), ring(j + 1, s)))
    return verts, faces


def write(name, verts, faces):
    with open("scenes/meshes/%s.obj" % name, "w") as f:
        f.write("# %s: made by scripts/make_meshes.py\n" % name)
        for v in verts:
            f.write("v %.5f %.5f %.5f\n" % v)
        for a, b, c in faces:
            f.write("f %d %d %d\n" % (a + 1, b + 1, c + 1))


def main():
    os.makedirs("scenes/meshes", exist_ok=True)
    write("urn", *revolve(PROFILE))
    write("bowl", *revolve(BOWL))
    write("bunny", *bunny())


if __name__ == "__main__":
    main()
