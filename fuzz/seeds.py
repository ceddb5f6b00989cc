#!/usr/bin/env python3
"""Writes the fuzz targets' seed inputs (docs/testing.md, "Fuzzing") into fuzz/seeds/TARGET/:
bundles (the main file, then `=== NAME` lines each starting a file it names) made from the
repository's assets/ and small files written here: a glTF with every part the loader reads
(accessors, sparse ones included, cameras, animations, lights, textures), as .gltf with a data
URI, with a .bin beside it and as .glb; OBJs with MTLs and textures; scene files with keyframes,
lenses, environment maps and aperture images. scripts/fuzz.sh merges them into fuzz/corpus/.
"""

import base64
import json
import os
import struct
import sys
import zlib

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
ASSETS = os.path.join(ROOT, "assets")
OUT = os.path.join(ROOT, "fuzz", "seeds")


# A 16 x 16 JPEG (ffmpeg from assets/apertures/heart.png, scaled, quality 5).
SMALL_JPEG = base64.b64decode(
    "/9j//gAQTGF2YzU5LjM3LjEwMAD/2wBDAAgKCgsKCw0NDQ0NDRAPEBAQEBAQEBAQEBASEhIVFRUSEhIQEBISFBQVFRcXFxUV"
    "FRUXFxkZGR4eHBwjIyQrKzP/xABZAAEAAAAAAAAAAAAAAAAAAAAGAQEAAAAAAAAAAAAAAAAAAAAAEAACAQMDBQEBAAAAAAAA"
    "AAABAgMEEQUyAAYzElExYRMhEQEAAAAAAAAAAAAAAAAAAAAA/8AAEQgAEAAQAwESAAISAAMSAP/aAAwDAQACEQMRAD8Aa4Li"
    "GAbB0gkooKhqimikkmdbys0iBiVk1IBey9pFh92A4LzmCihjxeTf840NqapOlAT05fCg6X9Afw2A2AP87xDALg6sR0UFO1PT"
    "SyRzItpVaNCwLSanBtZu4m4+7Ac65zBWwyYvGP8ApG5tU1I0uAenF5UnU/oj+C4OwD//2Q=="
)


def asset(*path):
    with open(os.path.join(ASSETS, *path), "rb") as f:
        return f.read()


def bundle(main, files=()):
    out = main
    for name, data in files:
        out += b"\n=== " + name.encode() + b"\n" + data
    return out


def png(width, height, rgba):
    """An RGBA8 PNG of `rgba` (bytes, row-major)."""
    rows = b"".join(b"\0" + rgba[y * width * 4:(y + 1) * width * 4] for y in range(height))

    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))

    header = struct.pack(">IIBBBBB", width, height, 8, 6, 0, 0, 0)
    return b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) + chunk(b"IDAT", zlib.compress(rows)) + chunk(b"IEND", b"")


def hdr(width, height):
    """A flat (uncompressed) Radiance HDR of a gradient."""
    head = b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y %d +X %d\n" % (height, width)
    pixels = b"".join(bytes([16 * x % 256, 16 * y % 256, 128, 129]) for y in range(height) for x in range(width))
    return head + pixels


def hdr_rle(width, height):
    """A Radiance HDR in run-length encoded scanlines (width 8 to 32767): each channel a run of
    its first value, then literals."""
    head = b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y %d +X %d\n" % (height, width)
    lines = b""
    for y in range(height):
        lines += bytes([2, 2, width >> 8, width & 255])
        for c in range(4):
            values = [129 if c == 3 else (16 * x + 32 * y + 64 * c) % 256 for x in range(width)]
            lines += bytes([128 + 4, values[0]]) + bytes([width - 4]) + bytes(values[4:])
    return head + lines


def write(target, name, data):
    folder = os.path.join(OUT, target)
    os.makedirs(folder, exist_ok=True)
    with open(os.path.join(folder, name), "wb") as f:
        f.write(data)


class Buffer:
    """A glTF binary buffer with its views and accessors."""

    def __init__(self):
        self.bin = b""
        self.views = []
        self.accessors = []

    def add(self, fmt, values, kind, component, count, min_max=None, target=None):
        while len(self.bin) % 4:
            self.bin += b"\0"
        data = struct.pack("<" + fmt * len(values), *values)
        view = {"buffer": 0, "byteOffset": len(self.bin), "byteLength": len(data)}
        if target:
            view["target"] = target
        self.views.append(view)
        self.bin += data
        accessor = {"bufferView": len(self.views) - 1, "componentType": component, "count": count, "type": kind}
        if min_max:
            accessor["min"], accessor["max"] = min_max
        self.accessors.append(accessor)
        return len(self.accessors) - 1


def gltf_document():
    """A glTF's JSON (without buffers' URIs) and its binary buffer."""
    b = Buffer()
    positions = [0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0.5, 0.5, 1]
    pos = b.add("f", positions, "VEC3", 5126, 5, ([0, 0, 0], [1, 1, 1]), 34962)
    nor = b.add("f", [0, 0, 1] * 5, "VEC3", 5126, 5)
    uv0 = b.add("f", [0, 0, 1, 0, 1, 1, 0, 1, 0.5, 0.5], "VEC2", 5126, 5)
    uv1 = b.add("H", [0, 0, 65535, 0, 65535, 65535, 0, 65535, 30000, 30000], "VEC2", 5123, 5)
    b.accessors[uv1]["normalized"] = True
    col = b.add("B", [255, 0, 0, 255] * 5, "VEC4", 5121, 5)
    b.accessors[col]["normalized"] = True
    tan = b.add("f", [1, 0, 0, 1] * 5, "VEC4", 5126, 5)
    idx = b.add("H", [0, 1, 2, 0, 2, 3, 2, 3, 4, 0], "SCALAR", 5123, 9, None, 34963)
    idx32 = b.add("I", [0, 1, 4], "SCALAR", 5125, 3)
    # A sparse accessor: positions with vertex 4 moved.
    sparse_idx = b.add("B", [4, 0, 0, 0], "SCALAR", 5121, 1)
    sparse_val = b.add("f", [0.5, 0.5, 2.0], "VEC3", 5126, 1)
    sparse = dict(b.accessors[pos])
    sparse["sparse"] = {
        "count": 1,
        "indices": {"bufferView": b.accessors[sparse_idx]["bufferView"], "componentType": 5121},
        "values": {"bufferView": b.accessors[sparse_val]["bufferView"]},
    }
    b.accessors.append(sparse)
    sparse_pos = len(b.accessors) - 1
    times = b.add("f", [0, 0.5, 1], "SCALAR", 5126, 3, ([0], [1]))
    trans = b.add("f", [0, 0, 4, 1, 0, 4, 1, 1, 3], "VEC3", 5126, 3)
    rots = b.add("f", [0, 0, 0, 1, 0, 0.2588, 0, 0.9659, 0, 0.5, 0, 0.866], "VEC4", 5126, 3)
    spline = b.add("f", [0, 0, 0, 1, 1, 1, 0, 0, 0] * 3, "VEC3", 5126, 9)
    weights = b.add("f", [0, 1, 0.5], "SCALAR", 5126, 3)
    texture_transform = {"KHR_texture_transform": {"offset": [0.1, 0.2], "rotation": 0.3, "scale": [2, 2], "texCoord": 1}}
    doc = {
        "asset": {"version": "2.0", "generator": "lensray fuzz seeds"},
        "extensionsUsed": ["KHR_lights_punctual", "KHR_texture_transform", "KHR_materials_emissive_strength",
                           "KHR_materials_specular", "KHR_materials_clearcoat", "KHR_materials_transmission",
                           "KHR_materials_ior", "KHR_materials_volume", "KHR_materials_sheen"],
        "scene": 0,
        "scenes": [{"nodes": [0, 3, 4, 5]}],
        "nodes": [
            {"name": "parent", "children": [1, 2], "translation": [0, 0.1, 0]},
            {"name": "cam", "camera": 0, "translation": [0.5, 0.5, 4]},
            {"name": "mesh", "mesh": 0, "rotation": [0, 0, 0, 1], "scale": [1, 1, 1]},
            {"name": "ortho", "camera": 1, "matrix": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 5, 1]},
            {"name": "lights", "mesh": 1, "extensions": {"KHR_lights_punctual": {"light": 0}}},
            {"name": "spot", "translation": [0, 2, 2], "extensions": {"KHR_lights_punctual": {"light": 1}}},
        ],
        "cameras": [
            {"type": "perspective", "perspective": {"yfov": 0.7, "znear": 0.01, "zfar": 100, "aspectRatio": 1.5}},
            {"type": "orthographic", "orthographic": {"xmag": 2, "ymag": 1, "znear": 0.01, "zfar": 50}},
        ],
        "extensions": {"KHR_lights_punctual": {"lights": [
            {"type": "point", "color": [1, 0.9, 0.8], "intensity": 20, "range": 10},
            {"type": "spot", "intensity": 50, "spot": {"innerConeAngle": 0.2, "outerConeAngle": 0.5}},
            {"type": "directional", "intensity": 3},
        ]}},
        "meshes": [
            {"name": "quad", "primitives": [
                {"attributes": {"POSITION": pos, "NORMAL": nor, "TEXCOORD_0": uv0, "TEXCOORD_1": uv1,
                                "COLOR_0": col, "TANGENT": tan}, "indices": idx, "material": 0, "mode": 4},
                {"attributes": {"POSITION": pos}, "indices": idx32, "material": 1},
                {"attributes": {"POSITION": pos, "TEXCOORD_0": uv0}, "material": 2},
            ]},
            {"name": "strip", "primitives": [{"attributes": {"POSITION": pos}, "mode": 5}]},
        ],
        "materials": [
            {"name": "textured", "pbrMetallicRoughness": {
                "baseColorFactor": [1, 1, 1, 1], "baseColorTexture": {"index": 0, "extensions": texture_transform},
                "metallicFactor": 0.2, "roughnessFactor": 0.6, "metallicRoughnessTexture": {"index": 1, "texCoord": 1}},
             "normalTexture": {"index": 1, "scale": 0.5}, "occlusionTexture": {"index": 0},
             "emissiveTexture": {"index": 0}, "emissiveFactor": [1, 0.5, 0.2],
             "alphaMode": "MASK", "alphaCutoff": 0.4, "doubleSided": True,
             "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 4},
                            "KHR_materials_specular": {"specularFactor": 0.5}}},
            {"name": "glass", "alphaMode": "BLEND", "pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.5, 1, 0.5]},
             "extensions": {"KHR_materials_transmission": {"transmissionFactor": 0.9},
                            "KHR_materials_ior": {"ior": 1.5},
                            "KHR_materials_volume": {"thicknessFactor": 0.1, "attenuationColor": [1, 0.5, 0.5]},
                            "KHR_materials_clearcoat": {"clearcoatFactor": 1, "clearcoatTexture": {"index": 1}},
                            "KHR_materials_sheen": {"sheenColorFactor": [1, 1, 1], "sheenRoughnessFactor": 0.5}}},
            {"name": "plain"},
        ],
        "textures": [{"source": 0, "sampler": 0}, {"source": 1}],
        "samplers": [{"magFilter": 9729, "minFilter": 9987, "wrapS": 33648, "wrapT": 33071}],
        "animations": [
            {"name": "camera move", "channels": [
                {"sampler": 0, "target": {"node": 1, "path": "translation"}},
                {"sampler": 1, "target": {"node": 1, "path": "rotation"}},
                {"sampler": 2, "target": {"node": 0, "path": "scale"}},
            ], "samplers": [
                {"input": times, "output": trans, "interpolation": "LINEAR"},
                {"input": times, "output": rots, "interpolation": "STEP"},
                {"input": times, "output": spline, "interpolation": "CUBICSPLINE"},
            ]},
            {"name": "mesh spin", "channels": [
                {"sampler": 0, "target": {"node": 2, "path": "rotation"}},
                {"sampler": 1, "target": {"node": 2, "path": "weights"}},
            ], "samplers": [
                {"input": times, "output": rots},
                {"input": times, "output": weights},
            ]},
        ],
        "accessors": b.accessors,
        "bufferViews": b.views,
    }
    return doc, b.bin, sparse_pos


def glb(doc, binary):
    text = json.dumps(doc, separators=(",", ":")).encode()
    text += b" " * (-len(text) % 4)
    binary += b"\0" * (-len(binary) % 4)
    chunks = struct.pack("<I4s", len(text), b"JSON") + text + struct.pack("<I4s", len(binary), b"BIN\0") + binary
    return b"glTF" + struct.pack("<II", 2, 12 + len(chunks)) + chunks


def gltf_seeds():
    small = png(2, 2, bytes([255, 0, 0, 255, 0, 255, 0, 128, 0, 0, 255, 255, 255, 255, 255, 0]))
    normal = png(1, 1, bytes([128, 128, 255, 255]))
    doc, binary, sparse_pos = gltf_document()
    data_uri = "data:application/octet-stream;base64," + base64.b64encode(binary).decode()
    images = [{"uri": "data:image/png;base64," + base64.b64encode(small).decode()}, {"uri": "normal.png"}]
    embedded = dict(doc, buffers=[{"byteLength": len(binary), "uri": data_uri}], images=images)
    write("gltf", "all-parts-embedded", bundle(json.dumps(embedded, indent=1).encode(), [("normal.png", normal)]))
    beside = dict(doc, buffers=[{"byteLength": len(binary), "uri": "data.bin"}],
                  images=[{"uri": "tex%20a.png"}, {"uri": "textures/normal.png"}])
    write("gltf", "all-parts-files", bundle(json.dumps(beside).encode(),
                                            [("data.bin", binary), ("tex a.png", small), ("textures/normal.png", normal)]))
    # The GLB's images live in buffer views of its binary chunk.
    binary2 = binary + b"\0" * (-len(binary) % 4)
    views = list(doc["bufferViews"])
    views.append({"buffer": 0, "byteOffset": len(binary2), "byteLength": len(small)})
    binary2 += small + b"\0" * (-len(small) % 4)
    views.append({"buffer": 0, "byteOffset": len(binary2), "byteLength": len(normal)})
    binary2 += normal
    in_glb = dict(doc, bufferViews=views, buffers=[{"byteLength": len(binary2)}],
                  images=[{"bufferView": len(views) - 2, "mimeType": "image/png"},
                          {"bufferView": len(views) - 1, "mimeType": "image/png"}])
    write("gltf", "all-parts.glb", glb(in_glb, binary2))
    write("gltf", "box-textured", bundle(asset("BoxTextured", "BoxTextured.gltf"),
                                         [("BoxTextured0.bin", asset("BoxTextured", "BoxTextured0.bin")),
                                          ("CesiumLogoFlat.png", asset("BoxTextured", "CesiumLogoFlat.png"))]))
    write("gltf", "box-textured-embedded", asset("BoxTextured", "BoxTextured_embedded.gltf"))
    # lensray refuses sparse accessors in one line.
    sparse = json.loads(json.dumps(embedded))
    sparse["meshes"][0]["primitives"][1]["attributes"]["POSITION"] = sparse_pos
    write("gltf", "sparse", bundle(json.dumps(sparse).encode(), [("normal.png", normal)]))
    return small, glb(in_glb, binary2)


TINY_OBJ = b"""# two triangles
mtllib tiny.mtl
o quad
v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
vt 0 0
vt 1 0
vt 1 1
vn 0 0 1
usemtl red
f 1/1/1 2/2/1 3/3/1
usemtl textured
f -4/1 -2/3 -1
s 1
g second
f 1//1 3//1 4//1 2//1
l 1 2
p 3
"""

TINY_MTL = b"""newmtl red
Kd 0.8 0.1 0.1
Ks 0.5 0.5 0.5
Ns 100
Ke 0 0 0
d 1
illum 2
newmtl textured
Kd 1 1 1
map_Kd -s 2 2 1 tex.png
map_Bump -bm 0.5 normal.png
bump normal.png
map_d tex.png
map_Ks tex.png
map_Ns tex.png
Ni 1.5
Tr 0.2
Pr 0.4
Pm 0.1
"""


def obj_seeds(small):
    normal = png(1, 1, bytes([128, 128, 255, 255]))
    write("obj", "tiny", bundle(TINY_OBJ, [("tiny.mtl", TINY_MTL), ("tex.png", small), ("normal.png", normal)]))
    cornell = asset("cornell", "cornell.obj")
    cornell = cornell[:cornell.index(b"\n", 8000) + 1]
    write("obj", "cornell-mtl", bundle(cornell, [("cornell.mtl", asset("cornell", "cornell.mtl"))]))


def scene_seeds(scene_glb):
    tiny_obj = [("tiny.obj", TINY_OBJ.replace(b"mtllib tiny.mtl", b"mtllib m.mtl")), ("m.mtl", TINY_MTL)]
    pull = asset("spheres", "pull.toml").replace(b'mesh = "spheres.obj"', b'mesh = "tiny.obj"')
    write("scene", "pull", bundle(pull, tiny_obj))
    cornell = asset("cornell", "cornell.toml").replace(b'mesh = "cornell.obj"', b'mesh = "tiny.obj"')
    write("scene", "cornell", bundle(cornell, tiny_obj))
    everything = b"""mesh = "scene.glb"
camera_name = "cam"
smooth_normals = 30.0
units = "cm"
[camera]
focus_distance = 300.0
f_number = 2.8
sensor_height_mm = 24.0
[camera.lens]
prescription = "lens.dat"
[camera.aperture]
image = "heart.png"
[image]
width = 64
height = 48
spp = 4
fps = 12.0
[render]
shading = "lit"
environment = "sky.hdr"
environment_rotation = 90.0
environment_intensity = 0.5
bounces = 2
[[light]]
type = "spot"
position = [1.0, 1.9, 1.0]
direction = [0.0, -1.0, 0.0]
intensity = [3.0, 3.0, 3.0]
inner_cone_degrees = 10.0
outer_cone_degrees = 25.0
[[keyframe]]
frame = 1
focus_distance = 150.0
eye = [0.0, 100.0, 300.0]
interpolation = "smooth"
[[keyframe]]
frame = 24
focus_point = [0.0, 0.0, 0.0]
target = [0.0, 0.5, 0.0]
shift = [0.1, 0.0]
tilt = 5.0
exposure = 1.0
lens = "double-gauss-50"
interpolation = "hold"
[[keyframe]]
frame = 48
focus_at = [32, 24]
f_number = 4.0
"""
    write("scene", "everything", bundle(everything, [
        ("scene.glb", scene_glb), ("lens.dat", asset("lenses", "double-gauss-50.dat")),
        ("heart.png", asset("apertures", "heart.png")), ("sky.hdr", hdr(16, 8))]))
    thin = b"""mesh = "tiny.obj"
[camera]
projection = "orthographic"
eye = [0.0, 0.0, 5.0]
target = [0.0, 0.0, 0.0]
up = [0.0, 1.0, 0.0]
[camera.aperture]
blades = 6
rotation = 15.0
roundness = 0.3
aspect = 1.5
[render]
shading = "normal"
environment = [0.2, 0.2, 0.2]
background = [0.0, 0.0, 0.0]
[light]
type = "directional"
direction = [0.0, -1.0, 0.0]
intensity = [1.0, 1.0, 1.0]
"""
    write("scene", "thin", bundle(thin, tiny_obj))


def lens_seeds():
    for name in sorted(os.listdir(os.path.join(ASSETS, "lenses"))):
        write("lens", name, asset("lenses", name))


def environment_seeds():
    write("environment", "rle.hdr", hdr_rle(32, 16))
    write("environment", "flat.hdr", hdr(16, 8))


def exr_seed():
    """A small scanline OpenEXR (half RGB, no compression)."""
    width, height = 4, 2

    def attr(name, kind, value):
        return name + b"\0" + kind + b"\0" + struct.pack("<I", len(value)) + value

    channels = b"".join(c + b"\0" + struct.pack("<iBBBBii", 1, 0, 0, 0, 0, 1, 1) for c in (b"B", b"G", b"R")) + b"\0"
    box = struct.pack("<iiii", 0, 0, width - 1, height - 1)
    header = (struct.pack("<ii", 20000630, 2) + attr(b"channels", b"chlist", channels)
              + attr(b"compression", b"compression", b"\0") + attr(b"dataWindow", b"box2i", box)
              + attr(b"displayWindow", b"box2i", box) + attr(b"lineOrder", b"lineOrder", b"\0")
              + attr(b"pixelAspectRatio", b"float", struct.pack("<f", 1))
              + attr(b"screenWindowCenter", b"v2f", struct.pack("<ff", 0, 0))
              + attr(b"screenWindowWidth", b"float", struct.pack("<f", 1)) + b"\0")
    table_at = len(header)
    lines = []
    for y in range(height):
        pixels = b"".join(struct.pack("<e", (c + x + y) / 8) for c in range(3) for x in range(width))
        lines.append(struct.pack("<ii", y, len(pixels)) + pixels)
    offsets, at = [], table_at + 8 * height
    for line in lines:
        offsets.append(at)
        at += len(line)
    return header + b"".join(struct.pack("<Q", o) for o in offsets) + b"".join(lines)


def image_seeds(small):
    write("image", "tiny.png", small)
    write("image", "heart.png", asset("apertures", "heart.png"))
    write("image", "logo.png", asset("BoxTextured", "CesiumLogoFlat.png"))
    write("image", "grey.png", png(3, 1, bytes([10, 10, 10, 255, 128, 128, 128, 255, 250, 250, 250, 255])))
    write("image", "flat.hdr", hdr(4, 2))
    write("image", "small.exr", exr_seed())
    write("image", "small.jpg", SMALL_JPEG)


def main():
    small, scene_glb = gltf_seeds()
    obj_seeds(small)
    scene_seeds(scene_glb)
    lens_seeds()
    environment_seeds()
    write("environment", "small.exr", exr_seed())
    image_seeds(small)
    print("seeds written to", OUT, file=sys.stderr)


if __name__ == "__main__":
    main()
