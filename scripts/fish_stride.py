#!/usr/bin/env python3
"""A driven fish's steady speed against its tail-beat frequency, beside what real fish do: writes a
table (stdout) and a plot (SVG). Runs reel on one fish of each length, beating at full amplitude,
and measures its centre of mass from 2 s (speed reached) to 5 s.

    python3 scripts/fish_stride.py build/release/reel docs/images/fish_stride.svg

Beside it: Bainbridge's (1958) fit for dace, goldfish and trout, U = L (3f - 4) / 4, and the
stride of 0.6-0.8 lengths a beat that fish keep in steady swimming (Videler 1993, "Fish
Swimming", ch. 8). Speeds are in lengths per second.
"""
import json
import os
import subprocess
import sys
import tempfile

from svg_axes import axes

LENGTHS = (0.3, 1.0)
FREQS = (0.5, 1.0, 1.5, 2.0, 2.5, 3.0, 3.5, 4.0)


def centre(frame):
    p = frame["bodies"][0]["positions"]
    return [sum(q[k] for q in p) / len(p) for k in range(3)]


def speed(reel, length, hz, tmp):
    scene = {"format": "reel/1", "fps": 30, "substeps": 10, "duration": 5.1, "integrator": "implicit_euler",
             "water": {"density": 1000},
             "bodies": [{"type": "fish", "name": "f", "behaviour": "none", "length": length,
                         "drive": {"swim": {"frequency": hz, "amplitude": 1}}}]}
    path = os.path.join(tmp, "fish.json")
    with open(path, "w") as f:
        json.dump(scene, f)
    subprocess.run([reel, "simulate", path, "--dump", path + ".dump", "-q"], check=True, capture_output=True)
    with open(path + ".dump") as f:
        frames = json.load(f)["frames"]
    a, b = centre(frames[60]), centre(frames[150])
    return sum((x - y) ** 2 for x, y in zip(a, b)) ** 0.5 / 3.0 / length


def main():
    reel, svg = sys.argv[1], sys.argv[2]
    rows = {}
    with tempfile.TemporaryDirectory() as tmp:
        for L in LENGTHS:
            rows[L] = [(f, speed(reel, L, f, tmp)) for f in FREQS]
    print("f (1/s)  " + "  ".join("U/L at %.1f m (stride)" % L for L in LENGTHS))
    for k, f in enumerate(FREQS):
        print("%-8.1f " % f + "  ".join("%6.2f (%.2f)          " % (rows[L][k][1], rows[L][k][1] / f) for L in LENGTHS))

    W, H, L0, B = 560, 380, 50, 40
    FMAX, UMAX = 4.0, 3.5
    px = lambda f, u: (L0 + f / FMAX * (W - L0 - 15), H - B - u / UMAX * (H - B - 15))
    out = axes(W, H, L0, B, px, range(0, 5), range(0, 4), "tail beats per second", "speed, lengths per second")
    # Videler's band of strides, 0.6-0.8 lengths a beat.
    band = [px(0, 0), px(FMAX, 0.8 * FMAX), px(FMAX, 0.6 * FMAX)]
    out.append('<polygon points="%s" fill="#2e8b57" fill-opacity="0.15"/>' % " ".join("%.1f,%.1f" % p for p in band))
    # Bainbridge's fit, where it is positive.
    a, b = px(4.0 / 3.0, 0), px(FMAX, (3 * FMAX - 4) / 4)
    out.append('<line x1="%.1f" y1="%.1f" x2="%.1f" y2="%.1f" stroke="#c0392b" stroke-width="2" stroke-dasharray="6,4"/>' % (*a, *b))
    colours = {0.3: "#1f5fbf", 1.0: "#e67e22"}
    for L in LENGTHS:
        path = " ".join("%s%.1f,%.1f" % ("M" if k == 0 else "L", *px(f, u)) for k, (f, u) in enumerate(rows[L]))
        out.append('<path d="%s" fill="none" stroke="%s" stroke-width="2"/>' % (path, colours[L]))
        for f, u in rows[L]:
            out.append('<circle cx="%.1f" cy="%.1f" r="3" fill="%s"/>' % (*px(f, u), colours[L]))
    y = 28
    for L in LENGTHS:
        out.append('<line x1="%d" y1="%d" x2="%d" y2="%d" stroke="%s" stroke-width="2"/><text x="%d" y="%d">reel, a %.1f m fish</text>'
                   % (L0 + 10, y - 4, L0 + 30, y - 4, colours[L], L0 + 36, y, L))
        y += 18
    out.append('<line x1="%d" y1="%d" x2="%d" y2="%d" stroke="#c0392b" stroke-width="2" stroke-dasharray="6,4"/>'
               '<text x="%d" y="%d">Bainbridge 1958: U = L(3f − 4)/4</text>' % (L0 + 10, y - 4, L0 + 30, y - 4, L0 + 36, y))
    y += 18
    out.append('<rect x="%d" y="%d" width="20" height="10" fill="#2e8b57" fill-opacity="0.15"/>'
               '<text x="%d" y="%d">0.6–0.8 lengths a beat (Videler 1993)</text>' % (L0 + 10, y - 12, L0 + 36, y))
    out.append("</svg>")
    with open(svg, "w") as f:
        f.write("\n".join(out) + "\n")


if __name__ == "__main__":
    main()
