#!/usr/bin/env python3
"""Writes scenes/face.json: the muscle-driven face (docs/face.md).

  0-2 s      the head, turned away, turns to the camera; the eyes lead it;
  2-12.8 s   the six universal expressions, one after another, with blinks: happiness, surprise,
             sadness, anger, disgust, fear;
  12.8-15 s  a cut to a three-quarter view in layers mode: the lattice, the skull and the muscles
             (yellow relaxed, red contracted) as the face smiles again.
Run from the repository root: python3 scripts/make_face_scene.py
"""
import json

from make_rigid_scenes import write_scene

FPS = 30
HALF = 0.5 / FPS  # a cut: the camera's keys held to half a frame either side
EXPRESSIONS = ["happiness", "surprise", "sadness", "anger", "disgust", "fear"]
START, EACH = 2.0, 1.8  # s: the first expression's start, and each one's length


def activations():
    keys = [{"time": 0.0, "preset": "happiness", "amount": 0.0}]
    for i, name in enumerate(EXPRESSIONS):
        t0 = START + EACH * i
        keys.append({"time": round(t0 + 0.55, 3), "preset": name, "amount": 1.0})
        keys.append({"time": round(t0 + 1.25, 3), "preset": name, "amount": 1.0})
        keys.append({"time": round(t0 + EACH, 3), "preset": name, "amount": 0.0})
    t = START + EACH * len(EXPRESSIONS)
    keys.append({"time": round(t + 0.7, 3), "preset": "happiness", "amount": 1.0})
    return keys


def main():
    front = ([0.0, 0.0, 0.5], [0.0, -0.002, 0.0])
    three_quarter = ([0.31, 0.03, 0.37], [0.0, 0.0, 0.0])
    cut = START + EACH * len(EXPRESSIONS)
    scene = {
        "format": "reel/1", "name": "face", "duration": 15.0, "fps": FPS, "substeps": 2,
        "integrator": "implicit_euler", "implicit": {"cg_tolerance": 1e-3},
        "render": {"width": 1280, "height": 720, "samples": 4,
                   "background": {"top": [0.16, 0.19, 0.24], "bottom": [0.05, 0.055, 0.07]}},
        "camera": {"position": front[0], "target": front[1], "fov_deg": 30,
                   "keys": [{"time": 0, "position": front[0], "target": front[1]},
                            {"time": round(cut - HALF, 4), "position": front[0], "target": front[1]},
                            {"time": round(cut + HALF, 4), "position": three_quarter[0], "target": three_quarter[1]},
                            {"time": 15.0, "position": [0.34, 0.04, 0.32], "target": three_quarter[1]}]},
        "lights": [{"type": "directional", "direction": [-0.5, -0.45, -1.0], "color": [1.0, 0.95, 0.88],
                    "intensity": 1.25, "shadows": True},
                   {"type": "directional", "direction": [0.8, -0.1, -0.6], "color": [0.6, 0.7, 0.9], "intensity": 0.35},
                   {"type": "ambient", "color": [0.55, 0.58, 0.65], "intensity": 0.45}],
        "bodies": [{
            "type": "face", "name": "face",
            "keys": [{"time": 0.0, "rotation_deg": [4, 62, 0]}, {"time": 0.3, "rotation_deg": [4, 62, 0]},
                     {"time": 1.9, "rotation_deg": [0, 0, 0]}, {"time": cut, "rotation_deg": [0, 0, 0]},
                     {"time": 15.0, "rotation_deg": [-3, 8, 0]}],
            "gaze": [{"time": 0.0, "target": [0.25, 0.0, 0.4]}, {"time": 0.9, "target": front[0]},
                     {"time": 15.0, "target": front[0]}],
            "blinks": [1.15, 4.7, 8.4, 11.2, 14.2],
            "activations": activations(),
            "draw": [{"time": 0, "mode": "skin"}, {"time": cut, "mode": "layers"}],
        }],
    }
    header = ("// The muscle-driven face (Terzopoulos & Waters 1990; Lee, Terzopoulos & Waters 1995): the head turns\n"
              "// to the camera, runs through Ekman's six expressions with blinks, then shows its layers and muscles.\n"
              "// Made by scripts/make_face_scene.py. Docs: docs/face.md\n")
    write_scene("scenes/face.json", header, scene)


if __name__ == "__main__":
    main()
