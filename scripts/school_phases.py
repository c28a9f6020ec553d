#!/usr/bin/env python3
"""Couzin et al. (2002), Fig. 2: the collective states of N = 100 agents of the zonal model against
the width of the zone of orientation, dr_o = r_o - r_r, at a zone of attraction dr_a = r_a - r_o = 14
(r_r = 1, speed 3, 40 deg/s, noise 0.05, 270 deg, tau = 0.1, the scene stepping at tau). For each
dr_o and seed, reel simulates 150 s from a random start in a ball of radius 4 and writes the order
parameters per frame (reel simulate --stats); the script averages polarisation p and milling m
over the last 50 s and writes a table (stdout) and a plot (SVG).

    python3 scripts/school_phases.py build/release/reel docs/images/school_phases.svg [seeds]

It then repeats the paper's Fig. 3, collective memory: dr_o rises slowly from 0.5 to 7 over
700 s (from a torus) and falls back over another 700 s (from a parallel group), with r_o keyed
over time in the scene ("orientation": [{"time", "value"}, ...]); p and m are averaged in bins of
dr_o for each leg and plotted beside the first SVG (name_hysteresis.svg).
"""
import csv
import os
import subprocess
import sys
import tempfile

SWEEP = [0, 0.5, 1, 1.5, 2, 3, 4, 5, 6, 8, 10, 12, 14, 15]
D_ATTRACT, DURATION, TAIL = 14.0, 150.0, 500  # frames of the average (50 s at 10 fps)


def scene(d_o, seed):
    ro = 1 + d_o
    return ('{"format": "reel/1", "name": "phase", "fps": 10, "substeps": 1, "duration": %g, "seed": %d,'
            ' "bodies": [{"type": "school", "name": "s", "count": 100, "start": {"center": [0, 0, 0], "radius": 4},'
            ' "zones": {"repulsion": 1, "orientation": %g, "attraction": %g}}]}' % (DURATION, seed, ro, ro + D_ATTRACT))


def order(reel, d_o, seed, tmp):
    path = os.path.join(tmp, "phase.json")
    with open(path, "w") as f:
        f.write(scene(d_o, seed))
    stats = os.path.join(tmp, "phase.csv")
    subprocess.run([reel, "simulate", path, "--stats", stats], check=True, stdout=subprocess.DEVNULL)
    rows = list(csv.DictReader(open(stats)))[-TAIL:]
    return (sum(float(r["polarization"]) for r in rows) / len(rows), sum(float(r["milling"]) for r in rows) / len(rows))


def state(p, m):
    """The paper's names, by the order parameters."""
    if m > 0.5 and p < 0.4:
        return "torus"
    if p > 0.95:
        return "highly parallel"
    if p > 0.6:
        return "dynamic parallel"
    return "swarm"


def svg(results, out):
    w, h, x0, y0, x1, y1 = 640, 400, 60, 30, 610, 350
    sx = lambda d: x0 + (x1 - x0) * d / 15.0
    sy = lambda v: y1 - (y1 - y0) * v
    parts = ['<svg xmlns="http://www.w3.org/2000/svg" width="%d" height="%d" font-family="sans-serif" font-size="12">' % (w, h),
             '<rect width="100%" height="100%" fill="white"/>',
             '<line x1="%d" y1="%d" x2="%d" y2="%d" stroke="black"/>' % (x0, y1, x1, y1),
             '<line x1="%d" y1="%d" x2="%d" y2="%d" stroke="black"/>' % (x0, y0, x0, y1)]
    for d in range(0, 16, 3):
        parts.append('<text x="%.1f" y="%d" text-anchor="middle">%d</text>' % (sx(d), y1 + 16, d))
    for v in (0, 0.25, 0.5, 0.75, 1.0):
        parts.append('<text x="%d" y="%.1f" text-anchor="end">%.2f</text>' % (x0 - 6, sy(v) + 4, v))
    parts.append('<text x="%d" y="%d" text-anchor="middle">width of the zone of orientation, r_o - r_r (r_r = 1)</text>' % ((x0 + x1) // 2, h - 12))
    for key, colour, label in (("p", "#1f5fbf", "polarisation p"), ("m", "#c0392b", "milling m")):
        pts = []
        for d, runs in results:
            vals = [r[key] for r in runs]
            for v in vals:
                parts.append('<circle cx="%.1f" cy="%.1f" r="2.5" fill="%s" fill-opacity="0.45"/>' % (sx(d), sy(v), colour))
            pts.append("%.1f,%.1f" % (sx(d), sy(sum(vals) / len(vals))))
        parts.append('<polyline points="%s" fill="none" stroke="%s" stroke-width="2"/>' % (" ".join(pts), colour))
        ly = sy(0.62 if key == "p" else 0.56)
        parts.append('<text x="%d" y="%.1f" fill="%s">%s (mean of seeds, dots: each seed)</text>' % (x1 - 290, ly, colour, label))
    for d, name in ((0, "swarm"), (1.2, "torus"), (5, "dynamic parallel"), (13.5, "highly parallel")):
        parts.append('<text x="%.1f" y="%d" text-anchor="middle" fill="#555">%s</text>' % (sx(d), y0 + 60, name))
    parts.append("</svg>")
    open(out, "w").write("\n".join(parts) + "\n")


RAMP, LO, HI = 700.0, 0.5, 7.0


def ramp_scene(seed):
    keys = [(0.0, LO), (100.0, LO), (100.0 + RAMP, HI), (100.0 + 2 * RAMP, LO)]
    ro = ", ".join('{"time": %g, "value": %g}' % (t, 1 + d) for t, d in keys)
    return ('{"format": "reel/1", "name": "memory", "fps": 10, "substeps": 1, "duration": %g, "seed": %d,'
            ' "bodies": [{"type": "school", "name": "s", "count": 100, "start": {"center": [0, 0, 0], "radius": 4},'
            ' "zones": {"repulsion": 1, "orientation": [%s], "attraction": %g}}]}' % (100 + 2 * RAMP, seed, ro, 1 + HI + D_ATTRACT))


def hysteresis(reel, seeds, tmp):
    """Mean p and m per bin of dr_o, for the rising and the falling leg."""
    bins = {}
    for seed in seeds:
        path, stats = os.path.join(tmp, "memory.json"), os.path.join(tmp, "memory.csv")
        with open(path, "w") as f:
            f.write(ramp_scene(seed))
        subprocess.run([reel, "simulate", path, "--stats", stats], check=True, stdout=subprocess.DEVNULL)
        for r in csv.DictReader(open(stats)):
            t = float(r["time"]) - 100.0
            if t < 0:
                continue
            leg = "up" if t < RAMP else "down"
            d = LO + (HI - LO) * (t / RAMP if t < RAMP else 2 - t / RAMP)
            key = (leg, round(d * 2) / 2)
            acc = bins.setdefault(key, [0.0, 0.0, 0])
            acc[0] += float(r["polarization"])
            acc[1] += float(r["milling"])
            acc[2] += 1
    return {k: (v[0] / v[2], v[1] / v[2]) for k, v in bins.items()}


def hysteresis_svg(bins, out):
    w, h, x0, y0, x1, y1 = 640, 400, 60, 30, 610, 350
    sx = lambda d: x0 + (x1 - x0) * (d - LO) / (HI - LO)
    sy = lambda v: y1 - (y1 - y0) * v
    parts = ['<svg xmlns="http://www.w3.org/2000/svg" width="%d" height="%d" font-family="sans-serif" font-size="12">' % (w, h),
             '<rect width="100%" height="100%" fill="white"/>',
             '<line x1="%d" y1="%d" x2="%d" y2="%d" stroke="black"/>' % (x0, y1, x1, y1),
             '<line x1="%d" y1="%d" x2="%d" y2="%d" stroke="black"/>' % (x0, y0, x0, y1)]
    for d in range(1, 8):
        parts.append('<text x="%.1f" y="%d" text-anchor="middle">%d</text>' % (sx(d), y1 + 16, d))
    for v in (0, 0.25, 0.5, 0.75, 1.0):
        parts.append('<text x="%d" y="%.1f" text-anchor="end">%.2f</text>' % (x0 - 6, sy(v) + 4, v))
    parts.append('<text x="%d" y="%d" text-anchor="middle">r_o - r_r, changed slowly (r_r = 1, r_a - r_o = 14 at the widest)</text>' % ((x0 + x1) // 2, h - 12))
    styles = (("up", 0, "#1f5fbf", "", "p, r_o rising (from a torus)"), ("down", 0, "#1f5fbf", ' stroke-dasharray="6,4"', "p, r_o falling (from a parallel group)"),
              ("up", 1, "#c0392b", "", "m, r_o rising"), ("down", 1, "#c0392b", ' stroke-dasharray="6,4"', "m, r_o falling"))
    for n, (leg, k, colour, dash, label) in enumerate(styles):
        pts = ["%.1f,%.1f" % (sx(d), sy(v[k])) for (l, d), v in sorted(bins.items()) if l == leg]
        parts.append('<polyline points="%s" fill="none" stroke="%s" stroke-width="2"%s/>' % (" ".join(pts), colour, dash))
        parts.append('<line x1="%d" y1="%d" x2="%d" y2="%d" stroke="%s" stroke-width="2"%s/>' % (x1 - 300, y0 + 150 + 16 * n, x1 - 270, y0 + 150 + 16 * n, colour, dash))
        parts.append('<text x="%d" y="%d">%s</text>' % (x1 - 262, y0 + 154 + 16 * n, label))
    parts.append("</svg>")
    open(out, "w").write("\n".join(parts) + "\n")


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    reel, out = sys.argv[1], sys.argv[2]
    seeds = range(1, 1 + (int(sys.argv[3]) if len(sys.argv) > 3 else 4))
    results = []
    print("dr_o   p (mean)  m (mean)  state")
    with tempfile.TemporaryDirectory() as tmp:
        for d in SWEEP:
            runs = [dict(zip("pm", order(reel, d, s, tmp))) for s in seeds]
            p = sum(r["p"] for r in runs) / len(runs)
            m = sum(r["m"] for r in runs) / len(runs)
            print("%5.1f  %8.3f  %8.3f  %s" % (d, p, m, state(p, m)))
            results.append((d, runs))
    svg(results, out)
    with tempfile.TemporaryDirectory() as tmp:
        bins = hysteresis(reel, seeds, tmp)
    print("\nr_o - r_r  rising: p  m     falling: p  m")
    for d in sorted({d for _, d in bins}):
        u, v = bins.get(("up", d), (float("nan"),) * 2), bins.get(("down", d), (float("nan"),) * 2)
        print("%5.1f      %5.2f  %5.2f       %5.2f  %5.2f" % (d, u[0], u[1], v[0], v[1]))
    hysteresis_svg(bins, out.replace(".svg", "_hysteresis.svg"))


if __name__ == "__main__":
    main()
