#!/usr/bin/env python3
"""Writes the glTF 2.0 test files of tests/data/gltf/ (tests/cpu/test_gltf_import.cpp and
tests/gpu/test_gltf_import_render.cpp read them): one textured quad as a .gltf with data-URI
PNGs and as its .glb twin (the same JSON, the PNGs in the binary chunk's buffer views).

The quad spans [-1, 1]^2 in z = 0 facing +z, UVs (0, 0) at the top left in glTF's convention.
Material "layered": a 4 x 4 base colour checker (red / blue, sampler CLAMP_TO_EDGE x
MIRRORED_REPEAT) under KHR_texture_transform (offset, scale, rotation), a 2 x 1
metallic-roughness texture (left texel: roughness 0.2, metal 1; right: roughness 0.8, metal 0),
a flat normal map with scale 0.5, emissive factor x KHR_materials_emissive_strength, and
KHR_materials_ior, _specular, _clearcoat and _sheen; alphaMode MASK; doubleSided. The file also
lists KHR_materials_iridescence, which caustic does not map (reported once).

Two more quads, each as .gltf and .glb too: "leaf" (an RGBA base colour texture, alphaMode MASK:
cut-outs) and "glow" (an emissive texture with KHR_materials_emissive_strength); their comments
below say what they hold.

Usage: make_test_gltf.py OUTPUT_DIR   (writes quad, leaf and glow, .gltf and .glb)
Only the Python standard library; the output is deterministic (byte-identical on every run).
"""
import base64
import json
import os
import struct
import sys
import zlib


def png(width, height, rows, channels):
    """An 8-bit PNG (colour type 2 RGB or 6 RGBA), no interlace, filter 0 on every row."""
    def chunk(kind, data):
        body = kind + data
        return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body) & 0xFFFFFFFF)
    raw = b"".join(b"\x00" + bytes(row) for row in rows)
    colour_type = {3: 2, 4: 6}[channels]
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, colour_type, 0, 0, 0)) +
            chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))


RED, BLUE = (230, 40, 30), (20, 60, 220)
BASE = png(4, 4, [[c for x in range(4) for c in (RED if (x + y) % 2 == 0 else BLUE)] for y in range(4)], 3)
# glTF: roughness in G, metalness in B.
MR = png(2, 1, [[0, 51, 255, 0, 204, 0]], 3)
NORMAL = png(1, 1, [[128, 128, 255]], 3)
IMAGES = [("base", BASE), ("metallic_roughness", MR), ("normal", NORMAL)]

POSITIONS = [(-1.0, -1.0, 0.0), (1.0, -1.0, 0.0), (1.0, 1.0, 0.0), (-1.0, 1.0, 0.0)]
NORMALS = [(0.0, 0.0, 1.0)] * 4
UVS = [(0.0, 1.0), (1.0, 1.0), (1.0, 0.0), (0.0, 0.0)]
INDICES = [0, 1, 2, 0, 2, 3]


def geometry_bytes():
    pos = b"".join(struct.pack("<3f", *p) for p in POSITIONS)
    nrm = b"".join(struct.pack("<3f", *n) for n in NORMALS)
    uv = b"".join(struct.pack("<2f", *t) for t in UVS)
    idx = b"".join(struct.pack("<H", i) for i in INDICES) + b"\x00\x00"  # pad to 4
    return [pos, nrm, uv, idx]


def document(spec, image_entries, buffers, views):
    """The glTF JSON of the quad with `spec`'s extensionsUsed, samplers, textures and materials."""
    return {
        "asset": {"version": "2.0", "generator": "caustic tests/gltf/make_test_gltf.py"},
        **spec,
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0, "name": "quad"}],
        "meshes": [{"name": "quad", "primitives": [{
            "attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2}, "indices": 3, "material": 0}]}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [-1, -1, 0], "max": [1, 1, 0]},
            {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC3"},
            {"bufferView": 2, "componentType": 5126, "count": 4, "type": "VEC2"},
            {"bufferView": 3, "componentType": 5123, "count": 6, "type": "SCALAR"},
        ],
        "bufferViews": views,
        "buffers": buffers,
        "images": image_entries,
    }


QUAD = {
        "extensionsUsed": ["KHR_texture_transform", "KHR_materials_emissive_strength", "KHR_materials_ior",
                           "KHR_materials_specular", "KHR_materials_clearcoat", "KHR_materials_sheen",
                           "KHR_materials_iridescence"],
        "samplers": [{"wrapS": 33071, "wrapT": 33648}, {}],
        "textures": [{"source": 0, "sampler": 0}, {"source": 1, "sampler": 1}, {"source": 2, "sampler": 1}],
        "materials": [{
            "name": "layered",
            "pbrMetallicRoughness": {
                "baseColorFactor": [1.0, 1.0, 1.0, 1.0],
                "baseColorTexture": {"index": 0, "extensions": {"KHR_texture_transform": {
                    "offset": [0.25, 0.5], "scale": [2.0, 0.5], "rotation": 0.3}}},
                "metallicFactor": 1.0, "roughnessFactor": 1.0,
                "metallicRoughnessTexture": {"index": 1, "extensions": {"KHR_texture_transform": {
                    "offset": [0.25, 0.5], "scale": [2.0, 0.5], "rotation": 0.3}}},
            },
            "normalTexture": {"index": 2, "scale": 0.5},
            "emissiveFactor": [0.1, 0.2, 0.3],
            "alphaMode": "MASK", "alphaCutoff": 0.3, "doubleSided": True,
            "extensions": {
                "KHR_materials_emissive_strength": {"emissiveStrength": 4.0},
                "KHR_materials_ior": {"ior": 1.4},
                "KHR_materials_specular": {"specularFactor": 0.8, "specularColorFactor": [1.0, 0.9, 0.8]},
                "KHR_materials_clearcoat": {"clearcoatFactor": 0.5, "clearcoatRoughnessFactor": 0.2},
                "KHR_materials_sheen": {"sheenColorFactor": [0.3, 0.2, 0.1], "sheenRoughnessFactor": 0.6},
                "KHR_materials_iridescence": {"iridescenceFactor": 1.0},
            },
        }],
}


# "leaf": alpha cut-outs. An 8 x 8 RGBA base colour texture (green) whose alpha is 255 in columns
# 0, 1, 4, 5 and 0 in columns 2, 3, 6, 7 (stripes along v), sampler REPEAT, under
# KHR_texture_transform scale (2, 1) (four stripe pairs across the quad); baseColorFactor alpha
# 0.8 and alphaCutoff 0.4, so a point is cut out where the texture's alpha is below 0.5:
# bilinear filtering crosses 0.5 exactly on the texel edges between the columns, so the quad is
# solid for glTF u in [k/4, k/4 + 1/8) and cut out in [k/4 + 1/8, (k + 1)/4).
LEAF_TEXTURE = png(8, 8, [[c for x in range(8) for c in (40, 160, 30, 255 if x % 4 < 2 else 0)] for _ in range(8)], 4)
LEAF_IMAGES = [("leaf", LEAF_TEXTURE)]
LEAF = {
    "extensionsUsed": ["KHR_texture_transform"],
    "samplers": [{"wrapS": 10497, "wrapT": 10497}],
    "textures": [{"source": 0, "sampler": 0}],
    "materials": [{
        "name": "leaf",
        "pbrMetallicRoughness": {
            "baseColorFactor": [1.0, 1.0, 1.0, 0.8],
            "baseColorTexture": {"index": 0, "extensions": {"KHR_texture_transform": {"scale": [2.0, 1.0]}}},
            "metallicFactor": 0.0, "roughnessFactor": 1.0,
        },
        "alphaMode": "MASK", "alphaCutoff": 0.4, "doubleSided": True,
    }],
}

# "glow": an emission texture. A 2 x 1 sRGB emissive texture (left texel (255, 128, 0), right
# (0, 64, 255)), sampler CLAMP_TO_EDGE, times emissiveFactor (1, 0.5, 0.25) times
# KHR_materials_emissive_strength 3; a black (non-reflecting) base.
GLOW_TEXTURE = png(2, 1, [[255, 128, 0, 0, 64, 255]], 3)
GLOW_IMAGES = [("glow", GLOW_TEXTURE)]
GLOW = {
    "extensionsUsed": ["KHR_materials_emissive_strength"],
    "samplers": [{"wrapS": 33071, "wrapT": 33071}],
    "textures": [{"source": 0, "sampler": 0}],
    "materials": [{
        "name": "glow",
        "pbrMetallicRoughness": {"baseColorFactor": [0.0, 0.0, 0.0, 1.0], "metallicFactor": 0.0, "roughnessFactor": 1.0},
        "emissiveTexture": {"index": 0},
        "emissiveFactor": [1.0, 0.5, 0.25],
        "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 3.0}},
    }],
}


def write_gltf(path, spec, images):
    geo = geometry_bytes()
    blob, views = b"", []
    for part in geo:
        views.append({"buffer": 0, "byteOffset": len(blob), "byteLength": len(part)})
        blob += part
    uri = "data:application/octet-stream;base64," + base64.b64encode(blob).decode()
    entries = [{"name": n, "uri": "data:image/png;base64," + base64.b64encode(b).decode()} for n, b in images]
    doc = document(spec, entries, [{"byteLength": len(blob), "uri": uri}], views)
    with open(path, "w") as f:
        json.dump(doc, f, indent=1, sort_keys=True)
        f.write("\n")


def write_glb(path, spec, images):
    geo = geometry_bytes()
    blob, views = b"", []
    for part in geo + [b for _, b in images]:
        views.append({"buffer": 0, "byteOffset": len(blob), "byteLength": len(part)})
        blob += part
        blob += b"\x00" * (-len(blob) % 4)
    entries = [{"name": n, "mimeType": "image/png", "bufferView": 4 + i} for i, (n, _) in enumerate(images)]
    doc = document(spec, entries, [{"byteLength": len(blob)}], views)
    text = json.dumps(doc, sort_keys=True).encode()
    text += b" " * (-len(text) % 4)
    body = struct.pack("<I4s", len(text), b"JSON") + text + struct.pack("<I4s", len(blob), b"BIN\x00") + blob
    with open(path, "wb") as f:
        f.write(struct.pack("<4sII", b"glTF", 2, 12 + len(body)) + body)


if __name__ == "__main__":
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..", "data", "gltf")
    os.makedirs(out, exist_ok=True)
    for name, spec, images in [("quad", QUAD, IMAGES), ("leaf", LEAF, LEAF_IMAGES), ("glow", GLOW, GLOW_IMAGES)]:
        write_gltf(os.path.join(out, name + ".gltf"), spec, images)
        write_glb(os.path.join(out, name + ".glb"), spec, images)
