#!/usr/bin/env python3
"""Writes the seed corpus of fuzz_mesh into a folder: one small valid file per format, each
preceded by the byte that picks its extension (the order of io::kMeshExtensions:
.obj .ply .stl .gltf .glb). Usage: make_mesh_seeds.py OUT_DIR"""
import base64, json, os, struct, sys

out = sys.argv[1]
os.makedirs(out, exist_ok=True)
tetra = [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)]
faces = [(0, 2, 1), (0, 1, 3), (0, 3, 2), (1, 2, 3)]

def put(name, kind, data):
    with open(os.path.join(out, name), "wb") as f:
        f.write(bytes([kind]) + data)

obj = "mtllib t.mtl\no t\n" + "".join(f"v {x} {y} {z}\n" for x, y, z in tetra) + \
      "vt 0 0\nvn 0 0 1\n" + "".join(f"f {a+1}/1/1 {b+1}/1/1 {c+1}/1/1\n" for a, b, c in faces) + "l 1 2\n"
put("tetra.obj", 0, obj.encode())
head = ("ply\nformat {}\ncomment reel\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
        "property uchar red\nproperty uchar green\nproperty uchar blue\n"
        "element face 4\nproperty list uchar int vertex_indices\nend_header\n")
put("tetra_ascii.ply", 1, (head.format("ascii 1.0") + "".join(f"{x} {y} {z} 255 0 0\n" for x, y, z in tetra) +
                           "".join(f"3 {a} {b} {c}\n" for a, b, c in faces)).encode())
body = b"".join(struct.pack("<fffBBB", *p, 0, 255, 0) for p in tetra) + b"".join(struct.pack("<Biii", 3, *f) for f in faces)
put("tetra_binary.ply", 1, head.format("binary_little_endian 1.0").encode() + body)
def normal(a, b, c):
    u = [b[i] - a[i] for i in range(3)]; v = [c[i] - a[i] for i in range(3)]
    return (u[1]*v[2]-u[2]*v[1], u[2]*v[0]-u[0]*v[2], u[0]*v[1]-u[1]*v[0])
stl = "solid t\n"
for f in faces:
    p = [tetra[i] for i in f]
    stl += "facet normal {} {} {}\nouter loop\n".format(*normal(*p)) + "".join(f"vertex {x} {y} {z}\n" for x, y, z in p) + "endloop\nendfacet\n"
put("tetra_ascii.stl", 2, (stl + "endsolid t\n").encode())
put("tetra_binary.stl", 2, b"reel".ljust(80, b" ") + struct.pack("<I", 4) +
    b"".join(struct.pack("<12fH", *normal(*[tetra[i] for i in f]), *sum([tetra[i] for i in f], ()), 0) for f in faces))
pos = b"".join(struct.pack("<3f", *p) for p in tetra)
idx = b"".join(struct.pack("<3H", *f) for f in faces)
def gltf(uri):
    return {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
            "nodes": [{"children": [1], "translation": [0, 1, 0]}, {"mesh": 0, "scale": [2, 2, 2]}],
            "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
            "buffers": [dict({"byteLength": len(pos) + len(idx)}, **({"uri": uri} if uri else {}))],
            "bufferViews": [{"buffer": 0, "byteLength": len(pos)}, {"buffer": 0, "byteOffset": len(pos), "byteLength": len(idx)}],
            "accessors": [{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 1]},
                          {"bufferView": 1, "componentType": 5123, "count": 12, "type": "SCALAR"}]}
put("tetra.gltf", 3, json.dumps(gltf("data:application/octet-stream;base64," + base64.b64encode(pos + idx).decode())).encode())
js = json.dumps(gltf(None)).encode(); js += b" " * (-len(js) % 4)
bn = pos + idx; bn += b"\0" * (-len(bn) % 4)
glb = struct.pack("<I", len(js)) + b"JSON" + js + struct.pack("<I", len(bn)) + b"BIN\0" + bn
put("tetra.glb", 4, b"glTF" + struct.pack("<II", 2, 12 + len(glb)) + glb)
