#!/usr/bin/env python3
"""The dam break against Martin & Moyce (1952): reads a reel dump of scenes/dam_break.json, finds
the surge front in every frame and writes it in their non-dimensional form beside their
measurements, as a table (stdout) and a plot (SVG).

    build/release/reel simulate scenes/dam_break.json --dump render_out/dam_break.dump.json --dump-every 1
    python3 scripts/dam_break.py render_out/dam_break.dump.json ../shared/data/martin_moyce_1952.csv \
        docs/images/dam_break.svg

The front is the largest x of a particle with at least two neighbours closer than the cutoff (so a
lone droplet thrown ahead does not count), measured from the back wall at x = 0. T = t*sqrt(2g/a),
Z = z/a with a = 0.1 m and g = 9.78 m/s^2 (the scene's).
"""
import json
import math
import sys

from svg_axes import axes

A, G, CUTOFF = 0.1, 9.78, 0.0082


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


def main():
    dump, data, svg = sys.argv[1], sys.argv[2], sys.argv[3]
    with open(dump) as f:
        frames = json.load(f)["frames"]
    sim = [(fr["time"] * math.sqrt(2 * G / A), front(fr["bodies"][0]["positions"]) / A) for fr in frames]
    measured = {}
    with open(data) as f:
        for line in f:
            if line.startswith("#") or not line.strip():
                continue
            a, t, z = (float(v) for v in line.split(","))
            measured.setdefault(a, []).append((t, z))

    def at(T):
        for (t0, z0), (t1, z1) in zip(sim, sim[1:]):
            if t0 <= T <= t1:
                return z0 + (z1 - z0) * (T - t0) / (t1 - t0)
        return None

    print("| T | Z measured (a = 1.125 in) | Z measured (a = 2.25 in) | Z reel |")
    print("|---|---|---|---|")
    rows = sorted({round(t, 3) for pts in measured.values() for t, _ in pts})
    for T in rows:
        cols = []
        for a in sorted(measured):
            z = [z for t, z in measured[a] if round(t, 3) == T]
            cols.append("%.2f" % z[0] if z else "")
        z = at(T)
        print("| %.2f | %s | %s |" % (T, " | ".join(cols), "%.2f" % z if z is not None else "(beyond the run)"))

    # The plot: 520 x 360 px, T in [0, 10], Z in [0, 14].
    W, H, L, B, TMAX, ZMAX = 520, 360, 50, 40, 10.0, 14.0
    def px(t, z):
        return L + (W - L - 15) * t / TMAX, H - B - (H - B - 15) * z / ZMAX
    out = axes(W, H, L, B, px, range(0, 11), range(0, 15, 2), "T = t·√(2g/a)", "Z = z/a")
    path = " ".join("%s%.1f,%.1f" % ("M" if k == 0 else "L", *px(t, z)) for k, (t, z) in enumerate(sim) if t <= TMAX)
    out.append('<path d="%s" fill="none" stroke="#1f5fbf" stroke-width="2"/>' % path)
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
    out.append('<line x1="%d" y1="24" x2="%d" y2="24" stroke="#1f5fbf" stroke-width="2"/><text x="%d" y="28">reel</text>' % (L + 10, L + 30, L + 36))
    out.append('<circle cx="%d" cy="42" r="4" fill="none" stroke="#c0392b"/><text x="%d" y="46">Martin &amp; Moyce, a = 1.125 in</text>' % (L + 20, L + 36))
    out.append('<rect x="%d" y="56.5" width="7" height="7" fill="none" stroke="#e67e22"/><text x="%d" y="64">Martin &amp; Moyce, a = 2.25 in</text>' % (L + 16.5, L + 36))
    out.append("</svg>")
    with open(svg, "w") as f:
        f.write("\n".join(out) + "\n")


if __name__ == "__main__":
    main()
