#!/usr/bin/env python3
"""The dam break against Martin & Moyce (1952): reads reel dumps of scenes/dam_break.json (the
divergence-free SPH model) and tests/scenes/dam_break_pairs.json (the seed's pair model), finds the
surge front in every frame and writes it in their non-dimensional form beside their measurements,
as a table (stdout) and a plot (SVG).

    build/release/reel simulate scenes/dam_break.json --dump render_out/dam_break.dump.json --dump-every 1
    build/release/reel simulate tests/scenes/dam_break_pairs.json --dump render_out/dam_break_pairs.dump.json --dump-every 1
    python3 scripts/dam_break.py tests/data/martin_moyce_1952.csv docs/images/dam_break.svg \
        render_out/dam_break.dump.json render_out/dam_break_pairs.dump.json

The front is the largest x of a particle with at least two neighbours closer than 8.2 mm (so a
lone droplet thrown ahead does not count), measured from the back wall at x = 0. T = t*sqrt(2g/a),
Z = z/a with a = 0.1 m and g = 9.78 m/s^2 (the scenes').
"""
import json
import math
import sys

from svg_axes import axes

A, G, CUTOFF = 0.1, 9.78, 0.0082
COLOURS = ["#1f5fbf", "#7f8c8d", "#27ae60"]


def front(positions):
    cells = {}
    for i, p in enumerate(positions):
        cells.setdefault(tuple(int(math.floor(c / CUTOFF)) for c in p), []).append(i)
    best = 0.0
    for i, p in enumerate(positions):
        if p[0] <= best:
            continue
        c = tuple(int(math.floor(v / CUTOFF)) for v in p)
        near = 0
        for dx in (-1, 0, 1):
            for dy in (-1, 0, 1):
                for dz in (-1, 0, 1):
                    for j in cells.get((c[0] + dx, c[1] + dy, c[2] + dz), ()):
                        if j != i and sum((a - b) ** 2 for a, b in zip(p, positions[j])) < CUTOFF ** 2:
                            near += 1
        if near >= 2:
            best = p[0]
    return best


def read_run(path):
    with open(path) as f:
        dump = json.load(f)
    sim = [(fr["time"] * math.sqrt(2 * G / A), front(fr["bodies"][0]["positions"]) / A) for fr in dump["frames"]]
    return dump.get("scene", path), sim


def at(sim, T):
    for (t0, z0), (t1, z1) in zip(sim, sim[1:]):
        if t0 <= T <= t1:
            return z0 + (z1 - z0) * (T - t0) / (t1 - t0)
    return None


def main():
    if len(sys.argv) < 4:
        sys.exit("usage: dam_break.py MEASUREMENTS.csv OUT.svg DUMP.json [DUMP.json ...]")
    data, svg, dumps = sys.argv[1], sys.argv[2], sys.argv[3:]
    runs = [read_run(d) for d in dumps]
    measured = {}
    with open(data) as f:
        for line in f:
            if line.startswith("#") or not line.strip():
                continue
            a, t, z = (float(v) for v in line.split(","))
            measured.setdefault(a, []).append((t, z))

    print("| T | Z measured (a = 1.125 in) | Z measured (a = 2.25 in) | " + " | ".join("Z %s" % n for n, _ in runs) + " |")
    print("|---|---|---|" + "---|" * len(runs))
    rows = sorted({round(t, 3) for pts in measured.values() for t, _ in pts})
    for T in rows:
        cols = []
        for a in sorted(measured):
            z = [z for t, z in measured[a] if round(t, 3) == T]
            cols.append("%.2f" % z[0] if z else "")
        for _, sim in runs:
            z = at(sim, T)
            cols.append("%.2f" % z if z is not None else "(beyond the run)")
        print("| %.2f | %s |" % (T, " | ".join(cols)))

    # The plot: 520 x 360 px, T in [0, 10], Z in [0, 14].
    W, H, L, B, TMAX, ZMAX = 520, 360, 50, 40, 10.0, 14.0
    def px(t, z):
        return L + (W - L - 15) * t / TMAX, H - B - (H - B - 15) * z / ZMAX
    out = axes(W, H, L, B, px, range(0, 11), range(0, 15, 2), "T = t·√(2g/a)", "Z = z/a")
    for k, (name, sim) in enumerate(runs):
        colour = COLOURS[k % len(COLOURS)]
        path = " ".join("%s%.1f,%.1f" % ("M" if i == 0 else "L", *px(t, z)) for i, (t, z) in enumerate(sim) if t <= TMAX)
        out.append('<path d="%s" fill="none" stroke="%s" stroke-width="2"/>' % (path, colour))
        y = 24 + 18 * k
        out.append('<line x1="%d" y1="%d" x2="%d" y2="%d" stroke="%s" stroke-width="2"/><text x="%d" y="%d">reel, %s</text>'
                   % (L + 10, y, L + 30, y, colour, L + 36, y + 4, name))
    marks = {1.125: ("#c0392b", "circle"), 2.25: ("#e67e22", "square")}
    for a, pts in sorted(measured.items()):
        colour, shape = marks.get(a, ("black", "circle"))
        for t, z in pts:
            if t > TMAX:
                continue
            x, y = px(t, z)
            if shape == "circle":
                out.append('<circle cx="%.1f" cy="%.1f" r="4" fill="none" stroke="%s" stroke-width="1.5"/>' % (x, y, colour))
            else:
                out.append('<rect x="%.1f" y="%.1f" width="7" height="7" fill="none" stroke="%s" stroke-width="1.5"/>' % (x - 3.5, y - 3.5, colour))
    y = 24 + 18 * len(runs)
    out.append('<circle cx="%d" cy="%d" r="4" fill="none" stroke="#c0392b"/><text x="%d" y="%d">Martin &amp; Moyce, a = 1.125 in</text>' % (L + 20, y, L + 36, y + 4))
    out.append('<rect x="%d" y="%.1f" width="7" height="7" fill="none" stroke="#e67e22"/><text x="%d" y="%d">Martin &amp; Moyce, a = 2.25 in</text>' % (L + 16.5, y + 14.5, L + 36, y + 22))
    out.append("</svg>")
    with open(svg, "w") as f:
        f.write("\n".join(out) + "\n")


if __name__ == "__main__":
    main()
