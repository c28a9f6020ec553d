#!/usr/bin/env python3
"""Writes scenes/face.json: the muscle-driven face (docs/face.md), a three-quarter close-up.

  0-2 s        the head, turned away, turns to the camera; the eyes lead it;
  2-11.6 s     the six universal expressions as one small performance, each flowing into the
               next without a return to a blank face, each held as long as it needs (a start
               of surprise is short, sadness lingers) and relaxing a little as it is held, with
               its carriage of the head and its gaze (sadness looks down, disgust and fear away),
               the eyes glancing about, with blinks: a smile of greeting, surprise, fear, anger,
               disgust, sadness;
  11.6-15.2 s  a spoken line's mouth shapes (visemes), the head nodding with it;
  15.2-18.1 s  the camera glides round to the other side as the head turns to it and the skin
               dissolves into the layers: the lattice over the left half, the skull and the
               muscles (red relaxed, a brighter red contracted) on the right, as the face smiles again;
  18.1-20.3 s  the skin comes back over them and the face ends smiling at the camera, the head and
               the camera at rest for the last 0.8 s.
Run from the repository root: python3 scripts/make_face_scene.py
"""
import json

from make_rigid_scenes import write_scene

FPS = 30
# The order tells a small story (greeting, a start, fear, anger pushing back, disgust, giving
# up); each one's length, s (summing to 9.6: a start of surprise is brief, sadness lingers).
EXPRESSIONS = ["happiness", "surprise", "fear", "anger", "disgust", "sadness"]
LENGTHS = [1.8, 1.1, 1.5, 1.6, 1.5, 2.1]
START = 2.0  # s: the first expression's start
STARTS = [START + sum(LENGTHS[:i]) for i in range(len(EXPRESSIONS))]
SPEECH = START + sum(LENGTHS)  # 11.6 s
# "Oh, hello. Maybe... who knows?" as visemes (time after SPEECH, s): a line whose shapes differ
# (a round "oh", the lips pressed for m and b, spread for "ee", pushed out for "who"), each held
# long enough to be seen (a line of quick, similar shapes read as the jaw opening and closing).
LINE = [(0.0, "rest"), (0.15, "oh"), (0.4, "oh"), (0.5, "rest"), (0.62, "ee"), (0.76, "th"), (0.9, "oh"), (1.2, "oh"),
        (1.35, "rest"), (1.55, "mbp"), (1.7, "ee"), (1.84, "mbp"), (1.98, "ee"), (2.25, "ee"), (2.4, "rest"),
        (2.55, "oo"), (2.8, "oo"), (2.9, "th"), (3.02, "oh"), (3.25, "oh"), (3.36, "th"), (3.5, "rest")]
CUT = SPEECH + 3.6  # 15.2 s: the skin starts to fade from the layers
FADE = 1.8  # s (at 1.2 a viewer saw the layers simply appear)
GLIDE_BEFORE, GLIDE_AFTER = 0.6, 1.2  # s: the camera's glide round to the layers' side, about CUT
# The layers held, then the skin comes back over them and the face ends smiling at the camera (a
# film that ended on the layers' figure ended on a debug view, viewers said).
BACK = CUT + 2.9  # 18.1 s: the skin starts to come back
BACK_FADE = 1.0  # s
LAST = ([-0.245, 0.035, 0.52], [0.0, -0.004, 0.0])  # the camera at the end, the crown and the collar in frame
END = BACK + 2.2  # 20.3 s
SETTLE = 0.8  # s: the head and the camera come to rest this long before the end


def activations():
    # At rest while the head turns to the camera (keys are eased between: without the key at
    # START the first smile would creep in over the whole turn).
    keys = [{"time": 0.0, "preset": "happiness", "amount": 0.0}, {"time": START, "preset": "happiness", "amount": 0.0}]
    # Each rises (a start of surprise fast, sadness slowly), holds while relaxing a little (a
    # face holding a mask still reads as a list of poses), and flows straight into the next;
    # only sadness lets go, into the line.
    for i, name in enumerate(EXPRESSIONS):
        t0, length = STARTS[i], LENGTHS[i]
        rise = 0.25 if name == "surprise" else 0.6 if name == "sadness" else 0.42
        keys.append({"time": round(t0 + rise, 3), "preset": name, "amount": 1.0})
        keys.append({"time": round(t0 + length - 0.05, 3), "preset": name, "amount": 0.8})
    keys.append({"time": round(SPEECH + 0.1, 3), "preset": "sadness", "amount": 0.0})
    # A faint smile while speaking (faint: its pull on the corners spread every mouth shape into
    # one grin), then the smile of the layers view.
    keys.append({"time": round(SPEECH + 0.3, 3), "preset": "happiness", "amount": 0.12})
    keys.append({"time": round(CUT - 0.2, 3), "preset": "happiness", "amount": 0.2})
    keys.append({"time": round(CUT + 0.9, 3), "preset": "happiness", "amount": 1.0})
    keys.append({"time": round(BACK, 3), "preset": "happiness", "amount": 0.85})
    keys.append({"time": round(END, 3), "preset": "happiness", "amount": 0.6})
    return keys


# Each expression's carriage of the head (degrees: chin down, turn to the face's left, tilt) and
# where its eyes go (None: the camera), so the head performs the feeling rather than holding
# still: the smile tilts, surprise pulls back, sadness drops the head and the eyes, anger lowers
# the chin and stares, disgust turns away, fear pulls back and looks aside.
# (The smile's tilt 2 degrees: at 6, in three-quarter view the far corner sank, and the smile read
# as a smirk.)
# (The eyes' targets within about 25 degrees of where the head points: turned further, with the
# head one way and the eyes the other, the irises sat in the lids' corners, cross-eyed; fear's
# within 10 degrees, since with the wider eyes an iris 25 degrees over in its corner, white all
# round the other, read as crossed.)
CARRIAGE = {"happiness": ([-3, 16, 2], None), "surprise": ([-7, 10, 0], None), "sadness": ([6, 16, -3], [0.05, -0.3, 0.4]),
            "anger": ([5, 8, 0], None), "disgust": ([-3, 27, -5], [0.3, -0.05, 0.36]), "fear": ([-5, 22, 3], [0.14, 0.08, 0.45])}


# How the head drifts while each expression holds (degrees, as CARRIAGE): a head that stops dead
# for a second reads as a held pose (viewers saw frames a second apart as the same picture); the
# drift carries on the feeling's motion (the smile tilts further, sadness sinks, disgust turns away).
DRIFT = {"happiness": [-1, 3, 1], "surprise": [2, -2, 0], "fear": [1, 3, 0], "anger": [2, -2, 0],
         "disgust": [-2, 3, -2], "sadness": [2, 2, -2]}


def head_keys():
    # Turned away, then toward the camera; each expression's carriage as it rises and holds,
    # moving on into the next; nods while it speaks.
    keys = [(0.0, [6, -58, 0]), (0.3, [6, -58, 0]), (1.8, [0, 12, 0])]
    for i, name in enumerate(EXPRESSIONS):
        t0, length = STARTS[i], LENGTHS[i]
        held = [a + b for a, b in zip(CARRIAGE[name][0], DRIFT[name])]
        keys.append((t0 + 0.55, CARRIAGE[name][0]))
        # (Not over a hold under half a second: surprise's drift over its 0.1 s jerked the head in
        # two frames, a viewer saw.)
        if length - 1.0 >= 0.5:
            keys.append((t0 + length - 0.45, held))
    keys += [(SPEECH + 0.5, [3, 14, 0]), (SPEECH + 1.3, [-2, 10, -2]), (SPEECH + 2.2, [4, 15, 1]),
             (CUT - GLIDE_BEFORE, [0, 12, 0]),
             # As the camera glides round, the head turns to it: lattice on the left half, muscles on the right.
             (CUT + GLIDE_AFTER, [2, -22, 0]), (BACK, [-2, -10, 0]),
             # Settled for the last moments, barely drifting (still moving into the last frame, the
             # film ended mid-move, a viewer said).
             (END - SETTLE, [-4, -13, 3]), (END, [-4.5, -13.5, 3])]
    return [{"time": round(t, 3), "rotation_deg": r} for t, r in keys]


def gaze_keys(camera, last):
    # The eyes lead the turn, then go where each expression sends them (the camera unless it says)
    # and glance away between expressions and while speaking.
    keys = [(0.0, [-0.3, 0.0, 0.3]), (0.8, camera)]
    for i, name in enumerate(EXPRESSIONS):
        t0, length = STARTS[i], LENGTHS[i]
        look = CARRIAGE[name][1] or camera
        keys += [(t0 + 0.2, look), (t0 + length - 0.4, look),
                 (t0 + length - 0.25, [0.15 * (-1) ** i, 0.05 - 0.08 * (i % 3 == 1), 0.4]), (t0 + length - 0.05, camera)]
    keys += [(SPEECH + 1.3, camera), (SPEECH + 1.45, [-0.12, 0.08, 0.4]), (SPEECH + 2.0, [-0.12, 0.08, 0.4]),
             (SPEECH + 2.15, camera), (CUT, camera),
             # Round to the camera on the layers' side as the head turns to it.
             (CUT + GLIDE_AFTER + 0.2, last), (END, last)]
    return [{"time": round(t, 3), "target": p} for t, p in keys]


def main():
    # (Far enough back that the crown stays in frame: cut off, the head read as cropped; with the
    # hair's fullness, 17.5 mm over the crown, a little farther and aimed higher.)
    close = ([0.19, 0.02, 0.56], [0.0, -0.009, 0.0])
    close_end = ([0.16, 0.02, 0.55], [0.0, -0.004, 0.0])
    layers = ([-0.27, 0.04, 0.52], [0.0, -0.02, 0.0])
    scene = {
        "format": "reel/1", "name": "face", "duration": round(END, 3), "fps": FPS, "substeps": 2,
        "integrator": "implicit_euler", "implicit": {"cg_tolerance": 1e-3},
        # Half a stop under (the background raised to match): at full exposure the key lit 40% of
        # the skin's pixels past 1 in red, and the clipped skin ran flat and yellow-peach, its form
        # gone (viewers: "uniform peach plastic"). Not ACES: its curve bleached the skin to a pale pink.
        "render": {"width": 1280, "height": 720, "samples": 4, "ao": {"radius": 0.025, "strength": 1.2}, "exposure": -0.5,
                   # A warm pool of light on the backdrop behind the head (a portrait's background
                   # light: a plain gradient read as a default render's void).
                   "background": {"top": [0.106, 0.12, 0.156], "bottom": [0.025, 0.028, 0.037],
                                  "glow": {"color": [0.11, 0.09, 0.07], "x": 0.52, "y": 0.62, "radius": 0.4}}},
        "camera": {"position": close[0], "target": close[1], "fov_deg": 30,
                   "keys": [{"time": 0, "position": close[0], "target": close[1]},
                            {"time": round(CUT - GLIDE_BEFORE, 4), "position": close_end[0], "target": close_end[1]},
                            {"time": round(CUT + GLIDE_AFTER, 4), "position": layers[0], "target": layers[1]},
                            {"time": round(BACK, 3), "position": [-0.23, 0.035, 0.47], "target": layers[1]},
                            {"time": round(END - SETTLE, 3), "position": LAST[0], "target": LAST[1]},
                            {"time": round(END, 3), "position": LAST[0], "target": LAST[1]}]},
        # Loop lighting: the key 21 degrees up and 27 to the far side of the face (the nose's
        # shadow falls short, beside it: higher, it lay on the upper lip as a dark smear viewers
        # took for a moustache; at 44 degrees to the side it lay under the near wing, where a
        # viewer saw dirt; a soft-box 30 degrees across, as close to a face as a portrait's (at 14 degrees, once the
        # shadow maps kept it, the near wing's shadow lay on the lip as a dark wedge viewers took for half a moustache)), a warm fill from the
        # camera's side at a tenth of it (at a fifth, then an eighth, viewers found the face
        # flat: the cheek toward the camera should turn into shadow; at a seventeenth, once the
        # shadow maps kept the nose's shadow, that shadow was near black under the wing), and a rim from
        # straight behind and above that lifts the head's outline off the background (from the side
        # it lit a band down the cheek; at 0.5 its sheen on the temple read as a hot streak), and a
        # bounce from below, steep, as a portrait's reflector under the chin gives (without it
        # the nose's underside and the wings' bottoms, lit by the ambient alone, joined into a dark
        # bar across the nose's base that a smile widened; with it, the key at 2.3 burnt the
        # forehead to near white).
        "lights": [{"type": "directional", "direction": [0.42, -0.36, -0.83], "color": [1.0, 0.93, 0.84],
                    "intensity": 2.05, "shadows": True, "angle_deg": 30},
                   {"type": "directional", "direction": [-0.8, -0.15, -0.5], "color": [0.95, 0.86, 0.8], "intensity": 0.205},
                   {"type": "directional", "direction": [0.0, -0.4, 1.0], "color": [0.9, 0.9, 1.0], "intensity": 0.32},
                   {"type": "directional", "direction": [0.1, 0.85, -0.5], "color": [1.0, 0.88, 0.8], "intensity": 0.25},
                   {"type": "ambient", "color": [0.62, 0.6, 0.6], "intensity": 0.1}],
        "bodies": [{
            "type": "face", "name": "face",
            # A man (the brow ridge, a wider jaw, a shaved beard's stubble): at 0.5 an
            # androgynous mannequin whose jaw viewers called narrow.
            "sex": 0.8, "build": 0.55,
            "keys": head_keys(),
            "gaze": gaze_keys(close[0], LAST[0]),
            "blinks": [1.0, 3.3, 6.1, 8.9, 12.3, 14.15, 16.4, 19.1],
            "activations": activations(),
            "visemes": [{"time": round(SPEECH + t, 3), "viseme": v} for t, v in LINE],
            "draw": [{"time": 0, "mode": "skin"}, {"time": round(CUT, 3), "mode": "layers", "fade": FADE},
                     {"time": round(BACK, 3), "mode": "skin", "fade": BACK_FADE}],
        }],
    }
    header = ("// The muscle-driven face (Terzopoulos & Waters 1990; Lee, Terzopoulos & Waters 1995) in a three-quarter\n"
              "// close-up: the head turns to the camera, runs through Ekman's six expressions, says a line, then shows\n"
              "// its layers and muscles. Made by scripts/make_face_scene.py. Docs: docs/face.md\n")
    write_scene("scenes/face.json", header, scene)


if __name__ == "__main__":
    main()
