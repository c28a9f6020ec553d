#!/usr/bin/env python3
"""Renders the face's documentation stills with reel itself:

  docs/images/face.png              a smile in a three-quarter view beside the layers and muscles
  docs/images/face_expressions.png  Ekman's six expressions in a row, unlabelled: happiness,
                                    surprise, sadness, anger, disgust, fear

Run from the repository root after building: python3 scripts/face_stills.py [build/release/reel]
"""
import json
import math
import os
import subprocess
import sys
import tempfile

EXPRESSIONS = ["happiness", "surprise", "sadness", "anger", "disgust", "fear"]
LIGHTS = [{"type": "directional", "direction": [0.6, -0.33, -0.62], "color": [1.0, 0.93, 0.84], "intensity": 2.2,
           "shadows": True, "angle_deg": 30},
          {"type": "directional", "direction": [-0.8, -0.15, -0.5], "color": [0.95, 0.86, 0.8], "intensity": 0.28},
          {"type": "directional", "direction": [0.0, -0.4, 1.0], "color": [0.9, 0.9, 1.0], "intensity": 0.32},
          {"type": "ambient", "color": [0.62, 0.6, 0.6], "intensity": 0.12}]
RENDER = {"samples": 4, "ao": {"radius": 0.025, "strength": 1.2},
          "background": {"top": [0.075, 0.085, 0.11], "bottom": [0.018, 0.02, 0.026]}}


def face(name, position, preset, draw="skin", turn=18, shoulders=True, look=None):
    look = look or [position[0] + 0.3, position[1], 0.8]
    return {"type": "face", "name": name, "position": position, "rotation_deg": [0, turn, 0], "shoulders": shoulders,
            "gaze": [{"time": 0, "target": look}],
            "activations": [{"time": 0, "preset": preset, "amount": 0}, {"time": 0.6, "preset": preset}],
            "draw": draw}


def scene(bodies, camera, width, height):
    return {"format": "reel/1", "duration": 1.0, "fps": 30, "substeps": 2, "integrator": "implicit_euler",
            "implicit": {"cg_tolerance": 1e-3}, "render": dict(RENDER, width=width, height=height),
            "camera": camera, "lights": LIGHTS, "bodies": bodies}


def still(reel, spec, out):
    with tempfile.NamedTemporaryFile("w", suffix=".json", delete=False) as f:
        json.dump(spec, f)
    try:
        subprocess.run([reel, "still", f.name, "--time", "0.9", "-o", out, "-q"], check=True)
    finally:
        os.unlink(f.name)


def main():
    reel = sys.argv[1] if len(sys.argv) > 1 else "build/release/reel"
    # Each head of the row turned 15 degrees from the camera, looking at it (turned alike, the heads
    # at the row's ends were seen nearly in profile, their eyes off to the side, and a viewer could
    # not name the last).
    eye = [0.0, 0.0, 1.05]
    row = [face(e, [0.22 * (i - 2.5), 0, 0], e, shoulders=False, look=eye,
                turn=15 + math.degrees(math.atan2(-0.22 * (i - 2.5), eye[2]))) for i, e in enumerate(EXPRESSIONS)]
    still(reel, scene(row, {"position": eye, "target": [0.0, -0.01, 0], "fov_deg": 17}, 1400, 320),
          "docs/images/face_expressions.png")
    pair = [face("smile", [-0.15, 0, 0], "happiness"), face("layers", [0.15, 0, 0], "happiness", "layers", 35)]
    still(reel, scene(pair, {"position": [0.03, -0.01, 0.62], "target": [0.0, -0.02, 0], "fov_deg": 26}, 960, 400),
          "docs/images/face.png")


if __name__ == "__main__":
    main()
