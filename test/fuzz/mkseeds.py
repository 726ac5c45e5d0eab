#!/usr/bin/env python3
"""Writes the seed corpus of the model-import fuzz target (test/fuzz/corpus/import), small inputs derived from
the shared scenes (../shared/scenes, see its SOURCES.md) and a few written here, in the form fuzz_import.c reads:
a kind digit, then the model, its companion file, a sidecar and a texture separated by "#hzfuzz-file#".

    python3 test/fuzz/mkseeds.py [SCENES_DIR] [OUT_DIR]

Run it again only to change the seeds; the fuzzer does not need it (its output is committed).
"""
import base64
import gzip
import io
import json
import os
import struct
import sys
import zipfile
import zlib

SEP = b"#hzfuzz-file#"
KIND = {"obj": b"0", "ply": b"1", "plygz": b"2", "gltf": b"3", "glb": b"4", "xml": b"5", "gzraw": b"6", "gltf7": b"7"}


def seed(kind, model, companion=None, sidecar=None, texture=None):
    parts = [model, companion or b"", sidecar or b"", texture or b""]
    while len(parts) > 1 and not parts[-1]:
        parts.pop()
    return KIND[kind] + SEP.join(parts)


def png_rgba(w, h, pixel):
    """A small RGBA PNG, pixel(x, y) -> (r, g, b, a)."""
    raw = b"".join(b"\0" + b"".join(bytes(pixel(x, y)) for x in range(w)) for y in range(h))

    def chunk(t, d):
        return struct.pack(">I", len(d)) + t + d + struct.pack(">I", zlib.crc32(t + d) & 0xFFFFFFFF)

    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 6, 0, 0, 0)) +
            chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))


def checker(x, y):
    on = (x + y) % 2
    return (255 * on, 128, 255 * (1 - on), 255 if x < 2 else 0)


def glb(doc, binary):
    js = json.dumps(doc, separators=(",", ":")).encode()
    js += b" " * (-len(js) % 4)
    binary += b"\0" * (-len(binary) % 4)
    body = struct.pack("<II", len(js), 0x4E4F534A) + js + struct.pack("<II", len(binary), 0x004E4942) + binary
    return struct.pack("<III", 0x46546C67, 2, 12 + len(body)) + body


def ply_subset(text, nverts):
    """The first nverts vertices of an ASCII PLY and the faces that use only them."""
    head, body = text.split("end_header\n", 1)
    lines = body.split("\n")
    nv = int([l for l in head.split("\n") if l.startswith("element vertex")][0].split()[2])
    verts = [tuple(float(v) for v in l.split()[:3]) for l in lines[:nverts]]
    faces = []
    for l in lines[nv:]:
        f = [int(v) for v in l.split()[1:]]
        if f and all(i < nverts for i in f):
            faces.append(f)
    return verts, faces


def ply_ascii(verts, faces):
    out = ["ply", "format ascii 1.0", "comment first vertices of the Stanford dragon (res4)",
           "element vertex %d" % len(verts), "property float x", "property float y", "property float z",
           "element face %d" % len(faces), "property list uchar int vertex_indices", "end_header"]
    out += ["%g %g %g" % v for v in verts]
    out += ["%d %s" % (len(f), " ".join(map(str, f))) for f in faces]
    return ("\n".join(out) + "\n").encode()


def ply_binary(verts, faces):
    head = ("ply\nformat binary_little_endian 1.0\nelement vertex %d\nproperty float x\nproperty float y\n"
            "property float z\nproperty float nx\nproperty float ny\nproperty float nz\nelement face %d\n"
            "property list uchar int vertex_indices\nend_header\n" % (len(verts), len(faces))).encode()
    body = b"".join(struct.pack("<6f", *v, 0.0, 1.0, 0.0) for v in verts)
    body += b"".join(struct.pack("<B%di" % len(f), len(f), *f) for f in faces)
    return head + body


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    scenes = sys.argv[1] if len(sys.argv) > 1 else os.path.join(here, "..", "..", "..", "shared", "scenes")
    out = sys.argv[2] if len(sys.argv) > 2 else os.path.join(here, "corpus", "import")
    sidecars = os.path.join(here, "..", "..", "tools", "bake", "scenes")
    os.makedirs(out, exist_ok=True)
    seeds = {}

    def sidecar(name):
        with open(os.path.join(sidecars, name + ".hzs"), "rb") as f:
            return f.read()

    # OBJ + MTL: the Cornell box, as shared.
    with zipfile.ZipFile(os.path.join(scenes, "CornellBox.zip")) as z:
        obj = z.read("CornellBox-Original.obj").replace(b"mtllib CornellBox-Original.mtl", b"mtllib m.mtl")
        mtl = z.read("CornellBox-Original.mtl")
    seeds["obj-cornell-box"] = seed("obj", obj, mtl, sidecar("CornellBox-Original"))

    # OBJ with UVs, normals, a diffuse and an alpha map, negative indices and a quad.
    tex = png_rgba(4, 4, checker)
    obj = (b"mtllib m.mtl\no leaf\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
           b"vn 0 0 1\nusemtl leaf\nf 1/1/1 2/2/1 3/3/1 4/4/1\no back\nv 0 0 -1\nv 1 0 -1\nv 1 1 -1\n"
           b"usemtl plain\nf -3 -2 -1\n")
    mtl = (b"newmtl leaf\nKd 0.5 0.8 0.3\nmap_Kd t.png\nmap_d t.png\nd 1\nnewmtl plain\nKd 0.9 0.9 0.9\n"
           b"Ks 0.5 0.5 0.5\n")
    side = (b"texture_max = 4\ncamera = 0 eye 0 0 3 target 0 0 0\ncamera = 0.2 eye 1 0 3 target 0 0 0\n"
            b"camera = 0.5 eye 1 1 3 target 0 0 0\n[material leaf]\nalpha_mode = mask\nalpha_cutoff = 0.5\n"
            b"[material plain]\nmirror = 0.5\n")
    seeds["obj-textured-quad"] = seed("obj", obj, mtl, side, tex)

    # PLY: the first vertices of the dragon, ASCII and binary (with normals), plain and gzipped.
    with gzip.open(os.path.join(scenes, "dragon", "dragon_vrip_res4.ply.gz"), "rt") as f:
        verts, faces = ply_subset(f.read(), 60)
    side = sidecar("dragon-res4")
    seeds["ply-ascii-dragon-piece"] = seed("ply", ply_ascii(verts, faces), None, side)
    seeds["ply-binary-dragon-piece"] = seed("ply", ply_binary(verts, faces))
    seeds["plygz-dragon-piece"] = seed("plygz", ply_ascii(verts, faces))
    seeds["gzraw-dragon-piece"] = seed("gzraw", gzip.compress(ply_ascii(verts, faces), 9, mtime=0))

    # glTF: BoxAnimated (rigid node animation), as .gltf + .bin and as .glb.
    box = os.path.join(scenes, "gltf", "BoxAnimated", "glTF")
    with open(os.path.join(box, "BoxAnimated.gltf")) as f:
        doc = json.load(f)
    with open(os.path.join(box, "BoxAnimated0.bin"), "rb") as f:
        binary = f.read()
    doc["buffers"][0]["uri"] = "m.bin"
    seeds["gltf-box-animated"] = seed("gltf", json.dumps(doc, indent=1).encode(), binary, sidecar("BoxAnimated"))
    del doc["buffers"][0]["uri"]
    seeds["glb-box-animated"] = seed("glb", glb(doc, binary), None, b"rigid_rate = 5\nanimation = 0\n")

    # glTF: AlphaBlendModeTest (alphaMode OPAQUE / MASK / BLEND), every image replaced by a 4x4 PNG.
    alpha = os.path.join(scenes, "gltf", "AlphaBlendModeTest", "glTF")
    with open(os.path.join(alpha, "AlphaBlendModeTest.gltf")) as f:
        doc = json.load(f)
    with open(os.path.join(alpha, "AlphaBlendModeTest.bin"), "rb") as f:
        binary = f.read()
    doc["buffers"][0]["uri"] = "m.bin"
    for im in doc.get("images", []):
        im["uri"] = "t.png"
        im.pop("mimeType", None)
    seeds["gltf-alpha-modes"] = seed("gltf", json.dumps(doc, separators=(",", ":")).encode(), binary,
                                     sidecar("AlphaBlendModeTest-small"), tex)

    # glTF: a skinned strip of two joints with a rotation animation, its buffer a data: URI; written here.
    pos = [(x, y, 0.0) for y in (0.0, 1.0, 2.0) for x in (0.0, 1.0)]
    idx = [0, 1, 3, 0, 3, 2, 2, 3, 5, 2, 5, 4]
    joints = [(0, 1, 0, 0)] * 2 + [(0, 1, 0, 0)] * 2 + [(1, 0, 0, 0)] * 2
    weights = [(1, 0, 0, 0)] * 2 + [(0.5, 0.5, 0, 0)] * 2 + [(1, 0, 0, 0)] * 2
    ibm = [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, -1, 0, 1]
    times = [0.0, 1.0, 2.0]
    rots = [(0, 0, 0, 1), (0, 0, 0.3826834, 0.9238795), (0, 0, 0, 1)]
    blob = b"".join(struct.pack("<3f", *p) for p in pos)  # 0: 72
    blob += struct.pack("<12H", *idx)  # 72: 24
    blob += b"".join(struct.pack("<4B", *j) for j in joints)  # 96: 24
    blob += b"".join(struct.pack("<4f", *w) for w in weights)  # 120: 96
    blob += struct.pack("<32f", *ibm)  # 216: 128
    blob += struct.pack("<3f", *times)  # 344: 12
    blob += b"".join(struct.pack("<4f", *r) for r in rots)  # 356: 48
    views = [(0, 72, 34962), (72, 24, 34963), (96, 24, 34962), (120, 96, 34962), (216, 128, None), (344, 12, None),
             (356, 48, None)]
    doc = {
        "asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0, 1]}],
        "nodes": [{"name": "strip", "mesh": 0, "skin": 0}, {"name": "root", "children": [2]},
                  {"name": "tip", "translation": [0, 1, 0]}],
        "meshes": [{"name": "strip", "primitives": [{"attributes": {"POSITION": 0, "JOINTS_0": 2, "WEIGHTS_0": 3},
                                                      "indices": 1, "material": 0}]}],
        "materials": [{"name": "skin", "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.6, 0.5, 1]}}],
        "skins": [{"joints": [1, 2], "inverseBindMatrices": 4}],
        "animations": [{"channels": [{"sampler": 0, "target": {"node": 2, "path": "rotation"}}],
                        "samplers": [{"input": 5, "output": 6, "interpolation": "LINEAR"}]}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 6, "type": "VEC3", "min": [0, 0, 0], "max": [1, 2, 0]},
            {"bufferView": 1, "componentType": 5123, "count": 12, "type": "SCALAR"},
            {"bufferView": 2, "componentType": 5121, "count": 6, "type": "VEC4"},
            {"bufferView": 3, "componentType": 5126, "count": 6, "type": "VEC4"},
            {"bufferView": 4, "componentType": 5126, "count": 2, "type": "MAT4"},
            {"bufferView": 5, "componentType": 5126, "count": 3, "type": "SCALAR", "min": [0], "max": [2]},
            {"bufferView": 6, "componentType": 5126, "count": 3, "type": "VEC4"}],
        "bufferViews": [dict({"buffer": 0, "byteOffset": o, "byteLength": n}, **({"target": t} if t else {}))
                        for o, n, t in views],
        "buffers": [{"byteLength": len(blob),
                     "uri": "data:application/octet-stream;base64," + base64.b64encode(blob).decode()}],
    }
    seeds["gltf-skinned-strip"] = seed("gltf", json.dumps(doc, indent=1).encode(), None,
                                       b"skin_rate = 4\nname = strip\nduration = 3\ncamera_loop = yes\n"
                                       b"light = position 0 1 3 color 5 5 5\ncamera = 0 eye 0 1 4 target 0 1 0\n"
                                       b"camera = 0.1 eye 2 1 3 target 0 1 0 fov 40\n"
                                       b"camera = 0.2 eye -2 2 3 target 0 1 0 up 0 1 0.1\n")
    seeds["gltf-skinned-strip-keys"] = seed("gltf", json.dumps(doc).encode(), None, b"skinning = keys\nskin_rate = 2\n")
    seeds["glb-skinned-strip-keys-no-normals"] = seed("glb", glb(dict(doc, buffers=[{"byteLength": len(blob)}]), blob),
                                                      None, b"skinning = keys\nskin_rate = 3\nnormals = none\n")

    # Furball: the first strands of the Embree furball (indices, then float4 points).
    with gzip.open(os.path.join(scenes, "furball", "furBall_A.bin.gz"), "rb") as f:
        data = f.read()
    nseg, pofs = 455505, 1822020
    idx = struct.unpack_from("<%dI" % 24, data, 0)
    npts = max(idx) + 2
    pts = data[pofs:pofs + 16 * npts]
    binary = struct.pack("<24I", *idx) + pts
    xml = ('<?xml version="1.0"?>\n<scene>\n  <assign type="scene" id="mesh1">\n    <RoundLineSegments>\n'
           '      <material>\n        <code>"Hair"</code>\n        <parameters>\n'
           '          <float3 name="Kt">0.64 0.456 0.256</float3>\n        </parameters>\n      </material>\n'
           '      <indices ofs="0" size="24"/>\n      <positions ofs="96" size="%d"/>\n'
           '    </RoundLineSegments>\n  </assign>\n</scene>\n' % npts).encode()
    assert nseg > 24
    seeds["xml-furball-strands"] = seed("xml", xml, binary, sidecar("furball"))
    seeds["xml-furball-ribbons"] = seed("xml", xml, binary, b"tube_sides = 1\ntube_radius_scale = 2\n")

    for name, data in sorted(seeds.items()):
        with open(os.path.join(out, name), "wb") as f:
            f.write(data)
        print("%-28s %6d bytes" % (name, len(data)))


if __name__ == "__main__":
    main()
