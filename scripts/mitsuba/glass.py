#!/usr/bin/env python3
"""lensray's glass (KHR_materials_transmission + _volume + _ior) against Mitsuba 3.

A glass ball (index 1.5, a volume, no absorption) in front of a checkered Lambert backdrop under
a uniform white sky, through a pinhole: once smooth (Mitsuba's `dielectric`), once rough (glTF
roughness r; Mitsuba's `roughdielectric`, GGX, alpha = r^2), each with 16 bounces and with one
(the reflection at the ball's front alone), and each rough and smooth ball alone under the sky
(a white furnace: what the glass loses). Four renderers per shot, each twice with different
seeds: lensray's CPU reference, Mitsuba with its own dielectric, Mitsuba with lensray's
dielectric model (`gltf_dielectric.py`: Schlick's Fresnel, height-correlated Smith, drawn as
Mitsuba draws), and the same with the exact Fresnel. Per region (the backdrop seen directly, the
ball by angle of incidence) the script gives each pair's mean difference against the noise the
seed pairs show: lensray against Mitsuba (the question), lensray against its model in Mitsuba
(lensray's estimator), Schlick against the exact Fresnel, and the rest of the model difference.
docs/mitsuba-glass.md explains the method and the figures; scripts/mitsuba/glass.sh installs
what it needs and runs it.

  glass.py --lensray BIN --out DIR [--width W --height H --spp N --mitsuba-spp N --roughness R]

Everything it writes goes to DIR: the scene files, the EXR renders, results.json, the PNGs.
"""

import argparse
import glob
import json
import math
import os
import struct
import subprocess
import sys
import time
import zlib

import numpy as np

# The shot. The eye sits off the axis so that a mirrored or shifted camera shows in the
# backdrop's check (the scene itself is symmetric about x = 0 and y = 0).
EYE, TARGET, UP = (0.9, 0.7, 5.0), (0.0, 0.0, 0.0), (0.0, 1.0, 0.0)
VFOV = 35.0
IOR = 1.5
BACKDROP_Z, BACKDROP_HALF = -4.5, 20.0
# An odd number of checks across a texture that spans the backdrop: the pattern reads the same
# with v or u flipped, so the two renderers' texture-coordinate conventions cannot differ.
CHECKS, TEXELS_PER_CHECK = 55, 8
CHECK_SRGB = ((225, 215, 190), (35, 70, 150))
# Sky radiance 1: a clear ball under it shows its Fresnel reflection directly (F x 1).
SKY = 1.0
# lensray's most bounces; Mitsuba's max_depth counts the camera ray's emitter hit as depth 1,
# so N shaded surfaces are max_depth N + 1.
BOUNCES = 16
# Regions of the ball by the angle of incidence at the pixel (degrees).
ANGLE_BINS = ((0, 30), (30, 45), (45, 60), (60, 70), (70, 80), (80, 90))


# --- files ------------------------------------------------------------------------------------


def write_png(path, rgb8):
    """An 8-bit RGB PNG from an (h, w, 3) uint8 array: zlib and the chunk CRCs, no imaging
    library (the venv has numpy only)."""
    h, w, _ = rgb8.shape
    raw = b"".join(b"\x00" + rgb8[y].tobytes() for y in range(h))

    def chunk(kind, data):
        return (struct.pack(">I", len(data)) + kind + data
                + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF))

    png = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0))
    png += chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b"")
    with open(path, "wb") as f:
        f.write(png)


def srgb8(linear):
    """Linear values -> sRGB bytes, clipped to [0, 1] (no tone map: the shot's values are
    under about 1.2)."""
    c = np.clip(linear, 0.0, 1.0)
    s = np.where(c <= 0.0031308, 12.92 * c, 1.055 * np.power(c, 1 / 2.4) - 0.055)
    return np.round(s * 255).astype(np.uint8)


def uv_sphere(stacks=96, slices=192):
    """A unit sphere: positions, exact normals (the positions), triangles wound
    counter-clockwise seen from outside (glTF's front faces), no degenerate ones at the poles."""
    positions = [(0.0, 1.0, 0.0)]
    for i in range(1, stacks):
        theta = math.pi * i / stacks
        for j in range(slices):
            phi = 2 * math.pi * j / slices
            positions.append((math.sin(theta) * math.sin(phi), math.cos(theta),
                              math.sin(theta) * math.cos(phi)))
    positions.append((0.0, -1.0, 0.0))
    p = np.array(positions, dtype=np.float64)
    p /= np.linalg.norm(p, axis=1, keepdims=True)
    ring = lambda i, j: 1 + (i - 1) * slices + j % slices  # noqa: E731
    tris = []
    for j in range(slices):
        tris.append((0, ring(1, j), ring(1, j + 1)))
        tris.append((len(p) - 1, ring(stacks - 1, j + 1), ring(stacks - 1, j)))
    for i in range(1, stacks - 1):
        for j in range(slices):
            a, b, c, d = ring(i, j), ring(i, j + 1), ring(i + 1, j), ring(i + 1, j + 1)
            tris += [(a, c, d), (a, d, b)]
    t = np.array(tris, dtype=np.uint32)
    # Wound outwards: each face's normal points away from the centre.
    e = np.cross(p[t[:, 1]] - p[t[:, 0]], p[t[:, 2]] - p[t[:, 0]])
    assert (np.einsum("ij,ij->i", e, p[t].mean(axis=1)) > 0).all()
    return p.astype(np.float32), p.astype(np.float32), t


def backdrop():
    """The backdrop: a square facing +Z, texture coordinates (0, 0) at its top left."""
    h, z = BACKDROP_HALF, BACKDROP_Z
    p = np.array([(-h, -h, z), (h, -h, z), (h, h, z), (-h, h, z)], dtype=np.float32)
    n = np.tile(np.array([0, 0, 1], dtype=np.float32), (4, 1))
    uv = np.array([(0, 1), (1, 1), (1, 0), (0, 0)], dtype=np.float32)
    return p, n, uv, np.array([(0, 1, 2), (0, 2, 3)], dtype=np.uint32)


def checker():
    size = CHECKS * TEXELS_PER_CHECK
    i = np.arange(size) // TEXELS_PER_CHECK
    parity = (i[:, None] + i[None, :]) % 2
    return np.array(CHECK_SRGB, dtype=np.uint8)[parity]


def write_ply(path, positions, normals, triangles, uv=None):
    """Binary little-endian PLY with the very triangles and vertex normals lensray reads."""
    cols = [positions, normals] + ([uv] if uv is not None else [])
    names = ["x", "y", "z", "nx", "ny", "nz"] + (["u", "v"] if uv is not None else [])
    vertex = np.hstack(cols).astype("<f4")
    face = np.empty(len(triangles), dtype=[("n", "u1"), ("i", "<u4", (3,))])
    face["n"], face["i"] = 3, triangles
    header = ["ply", "format binary_little_endian 1.0", f"element vertex {len(vertex)}"]
    header += [f"property float {name}" for name in names]
    header += [f"element face {len(face)}", "property list uchar uint vertex_indices", "end_header"]
    with open(path, "wb") as f:
        f.write(("\n".join(header) + "\n").encode())
        f.write(vertex.tobytes())
        f.write(face.tobytes())


def glass_material(roughness, double_sided):
    return {
        "name": "glass",
        "pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 1], "metallicFactor": 0.0,
                                 "roughnessFactor": roughness},
        "doubleSided": double_sided,
        "extensions": {"KHR_materials_transmission": {"transmissionFactor": 1.0},
                       "KHR_materials_ior": {"ior": IOR},
                       # thicknessFactor > 0: the mesh bounds a volume; no attenuation.
                       "KHR_materials_volume": {"thicknessFactor": 1.0}},
    }


def write_gltf(out, name, roughness, with_backdrop=True, double_sided=True):
    """`name`.gltf: the ball and (`with_backdrop`) the backdrop, sharing glass.bin and
    checker.png. The backdrop's `specularFactor` 0 takes glTF's specular lobe away: a Lambert
    surface, which is what Mitsuba's `diffuse` is."""
    sp, sn, st = uv_sphere()
    bp, bn, buv, bt = backdrop()
    blobs, views, accessors = [], [], []

    def add(array, target, kind="VEC3", component=5126, bounds=False):
        data = np.ascontiguousarray(array).tobytes()
        offset = sum(len(b) for b in blobs)
        blobs.append(data + b"\x00" * (-len(data) % 4))
        views.append({"buffer": 0, "byteOffset": offset, "byteLength": len(data),
                      "target": target})
        acc = {"bufferView": len(views) - 1, "componentType": component,
               "count": len(array) if kind != "SCALAR" else array.size, "type": kind}
        if bounds:
            acc["min"], acc["max"] = array.min(axis=0).tolist(), array.max(axis=0).tolist()
        accessors.append(acc)
        return len(accessors) - 1

    sphere = {"attributes": {"POSITION": add(sp, 34962, bounds=True), "NORMAL": add(sn, 34962)},
              "indices": add(st.ravel(), 34963, "SCALAR", 5125), "material": 1}
    plane = {"attributes": {"POSITION": add(bp, 34962, bounds=True), "NORMAL": add(bn, 34962),
                            "TEXCOORD_0": add(buv, 34962, "VEC2")},
             "indices": add(bt.ravel(), 34963, "SCALAR", 5125), "material": 0}
    with open(os.path.join(out, "glass.bin"), "wb") as f:
        f.write(b"".join(blobs))
    gltf = {
        "asset": {"version": "2.0", "generator": "lensray scripts/mitsuba/glass.py"},
        "extensionsUsed": ["KHR_materials_transmission", "KHR_materials_ior",
                           "KHR_materials_volume", "KHR_materials_specular"],
        "buffers": [{"uri": "glass.bin", "byteLength": sum(len(b) for b in blobs)}],
        "bufferViews": views, "accessors": accessors,
        "images": [{"uri": "checker.png"}],
        "samplers": [{"magFilter": 9729, "minFilter": 9987, "wrapS": 10497, "wrapT": 10497}],
        "textures": [{"source": 0, "sampler": 0}],
        "materials": [
            {"name": "backdrop", "doubleSided": True,
             "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}, "metallicFactor": 0.0,
                                      "roughnessFactor": 1.0},
             "extensions": {"KHR_materials_specular": {"specularFactor": 0.0}}},
            glass_material(roughness, double_sided)],
        "meshes": [{"name": "ball", "primitives": [sphere]},
                   {"name": "backdrop", "primitives": [plane]}],
        "nodes": [{"mesh": 0}, {"mesh": 1}],
        "scenes": [{"nodes": [0, 1] if with_backdrop else [0]}], "scene": 0,
    }
    with open(os.path.join(out, f"{name}.gltf"), "w") as f:
        json.dump(gltf, f, indent=1)
    return (sp, sn, st), (bp, bn, buv, bt)


def write_scenes(out, roughness):
    """The glTFs lensray reads, the checker, and the PLYs Mitsuba reads (the same triangles,
    vertex normals and texture coordinates)."""
    os.makedirs(out, exist_ok=True)
    write_png(os.path.join(out, "checker.png"), checker())
    sphere, plane = write_gltf(out, "smooth", 0.0)
    write_gltf(out, "rough", roughness)
    write_gltf(out, "smooth-furnace", 0.0, with_backdrop=False)
    write_gltf(out, "rough-furnace", roughness, with_backdrop=False)
    write_gltf(out, "smooth-single-sided", 0.0, double_sided=False)
    write_ply(os.path.join(out, "ball.ply"), *sphere)
    bp, bn, buv, bt = plane
    write_ply(os.path.join(out, "backdrop.ply"), bp, bn, bt, uv=buv)


# --- the renders ------------------------------------------------------------------------------


def lensray_render(args, scene, bounces, seed, out):
    """One lensray render on the CPU reference, linear EXR, the sky the only light."""
    cmd = [args.lensray, "render", "--scene", os.path.join(args.out, f"{scene}.gltf"),
           "--path", "cpu", "--shading", "lit", "--progress", "none",
           "--eye", ",".join(map(str, EYE)), "--target", ",".join(map(str, TARGET)),
           "--up", ",".join(map(str, UP)), "--vfov", str(VFOV), "--aperture-radius", "0",
           "--focus-distance", "5", "--width", str(args.width), "--height", str(args.height),
           "--spp", str(args.spp), "--seed", str(seed), "--environment", f"{SKY},{SKY},{SKY}",
           "--bounces", str(bounces), "--tonemap", "none", "--out", out]
    run = subprocess.run(cmd, capture_output=True, text=True)
    if run.returncode != 0:
        sys.exit(f"lensray failed: {' '.join(cmd)}\n{run.stderr}")


def mitsuba_scene(mi, args, model, roughness, bounces, with_backdrop):
    """The shot in Mitsuba, the ball's BSDF Mitsuba's own (`model` "mitsuba"), lensray's
    ("gltf") or lensray's with the exact Fresnel ("gltf-exact")."""
    if model.startswith("gltf"):
        bsdf = {"type": "gltf_dielectric", "ior": IOR, "roughness": roughness,
                "fresnel": "exact" if model == "gltf-exact" else "schlick"}
    elif roughness > 0:
        # lensray clamps roughness to 0.045 (alpha 0.002); r = 0.3 is far above.
        bsdf = {"type": "roughdielectric", "distribution": "ggx", "alpha": roughness ** 2,
                "int_ior": IOR, "ext_ior": 1.0}
    else:
        # ext_ior 1: Mitsuba's default outside is air, 1.000277.
        bsdf = {"type": "dielectric", "int_ior": IOR, "ext_ior": 1.0}
    scene = {
        "type": "scene",
        # rr_depth past max_depth: no Russian roulette, so both renderers end paths alike.
        "integrator": {"type": "path", "max_depth": bounces + 1, "rr_depth": 1000},
        "sensor": {
            "type": "perspective", "fov": VFOV, "fov_axis": "y",
            "near_clip": 1e-6, "far_clip": 1e7,
            "to_world": mi.ScalarTransform4f().look_at(origin=EYE, target=TARGET, up=UP),
            "film": {"type": "hdrfilm", "width": args.width, "height": args.height,
                     "rfilter": {"type": "box"}, "pixel_format": "rgb",
                     "component_format": "float32"},
            "sampler": {"type": "independent"},
        },
        "sky": {"type": "constant", "radiance": {"type": "rgb", "value": [SKY] * 3}},
        "ball": {"type": "ply", "filename": os.path.join(args.out, "ball.ply"), "bsdf": bsdf},
    }
    if with_backdrop:
        scene["backdrop"] = {
            "type": "ply", "filename": os.path.join(args.out, "backdrop.ply"),
            "bsdf": {"type": "diffuse", "reflectance": {
                "type": "bitmap", "filename": os.path.join(args.out, "checker.png"),
                "filter_type": "bilinear", "wrap_mode": "repeat"}},
        }
    return mi.load_dict(scene)


def read_exr(mi, path):
    bitmap = mi.Bitmap(path).convert(mi.Bitmap.PixelFormat.RGB, mi.Struct.Type.Float32,
                                     srgb_gamma=False)
    return np.array(bitmap, dtype=np.float64)


# --- regions ----------------------------------------------------------------------------------


def pixel_rays(width, height, sub=4):
    """Directions of sub x sub rays per pixel (a pinhole at EYE; row 0 at the top, +x to the
    right of the view), shape (height, width, sub*sub, 3)."""
    f = np.subtract(TARGET, EYE)
    f = f / np.linalg.norm(f)
    r = np.cross(f, UP)
    r /= np.linalg.norm(r)
    u = np.cross(r, f)
    t = math.tan(math.radians(VFOV) / 2)
    o = (np.arange(sub) + 0.5) / sub
    x = (np.arange(width)[:, None] + o[None, :]).ravel()
    y = (np.arange(height)[:, None] + o[None, :]).ravel()
    sx = (2 * x / width - 1) * t * width / height
    sy = (1 - 2 * y / height) * t
    d = f + sx[None, :, None] * r + sy[:, None, None] * u
    d /= np.linalg.norm(d, axis=-1, keepdims=True)
    d = d.reshape(height, sub, width, sub, 3).transpose(0, 2, 1, 3, 4)
    return d.reshape(height, width, sub * sub, 3)


def regions(width, height):
    """The regions compared, as pixel masks, from 4 x 4 rays a pixel against the ideal unit
    sphere: the ball's fully covered pixels (interior: under 60 degrees of incidence everywhere
    in the pixel, rim: the rest; and by the pixel's mean angle), the silhouette's partly covered
    ones, and the backdrop seen directly (two pixels or more from the ball), near the ball (within
    2.5 of the point behind its centre: most of the sky it sees passes through the glass) and
    far."""
    d = pixel_rays(width, height)
    e = np.array(EYE)
    b = d @ e
    disc = b * b - (e @ e - 1.0)
    hit = disc > 0
    t = -b - np.sqrt(np.where(hit, disc, 0))
    n = e + t[..., None] * d
    cos = np.clip(-np.einsum("...k,...k->...", d, n), 0, 1)
    angle = np.where(hit, np.degrees(np.arccos(cos)), np.nan)
    covered = hit.mean(axis=-1)
    full = covered == 1.0
    near_ball = covered > 0
    for _ in range(2):
        grown = near_ball.copy()
        grown[1:] |= near_ball[:-1]
        grown[:-1] |= near_ball[1:]
        grown[:, 1:] |= near_ball[:, :-1]
        grown[:, :-1] |= near_ball[:, 1:]
        near_ball = grown
    tb = (BACKDROP_Z - e[2]) / d[..., 2]
    pb = e + tb[..., None] * d
    on_backdrop = (np.abs(pb[..., :2]) <= BACKDROP_HALF).all(axis=-1).all(axis=-1)
    radial = np.hypot(pb[..., 0], pb[..., 1]).mean(axis=-1)
    backdrop = ~near_ball & on_backdrop
    max_angle = np.nanmax(np.where(hit, angle, -1), axis=-1)
    masks = {
        "backdrop, far": backdrop & (radial > 2.5),
        "backdrop, near ball": backdrop & (radial <= 2.5),
        "ball interior (< 60 deg)": full & (max_angle < 60),
        "ball rim (>= 60 deg)": full & (max_angle >= 60),
        "silhouette (part covered)": (covered > 0) & ~full,
    }
    mean_angle = np.where(full, np.where(hit, angle, 0).mean(axis=-1), np.nan)
    for lo, hi in ANGLE_BINS:
        masks[f"ball {lo}-{hi} deg"] = full & (mean_angle >= lo) & (mean_angle < hi)
    return masks


# --- Fresnel ----------------------------------------------------------------------------------


def fresnel_exact(cos_i, eta=IOR):
    """Unpolarized Fresnel reflectance of a smooth dielectric, from the outside."""
    cos_i = np.clip(cos_i, 0, 1)
    sin_t2 = (1 - cos_i ** 2) / eta ** 2
    cos_t = np.sqrt(np.clip(1 - sin_t2, 0, 1))
    rs = (cos_i - eta * cos_t) / (cos_i + eta * cos_t)
    rp = (eta * cos_i - cos_t) / (eta * cos_i + cos_t)
    return 0.5 * (rs * rs + rp * rp)


def fresnel_schlick(cos_i, eta=IOR):
    f0 = ((eta - 1) / (eta + 1)) ** 2
    return f0 + (1 - f0) * (1 - np.clip(cos_i, 0, 1)) ** 5


def fresnel_table():
    rows = []
    for deg in (0, 30, 45, 60, 70, 75, 80, 85, 89):
        c = math.cos(math.radians(deg))
        rows.append({"angle": deg, "schlick": float(fresnel_schlick(c)),
                     "exact": float(fresnel_exact(c))})
    return rows


# --- comparison -------------------------------------------------------------------------------

# The pairs compared: (label, first renderer, second renderer). lensray's model in Mitsuba
# ("gltf") and the same with the exact Fresnel ("gltf-exact") split lensray - Mitsuba into
# lensray's estimator, Schlick's share and the rest of the model.
PAIRS = (("lensray - Mitsuba", "lensray", "mitsuba"),
         ("lensray - model", "lensray", "gltf"),
         ("Schlick - exact", "gltf", "gltf-exact"),
         ("rest of model", "gltf-exact", "mitsuba"))


def pair_stats(a1, a2, b1, b2, mask):
    """Renderer a against renderer b, each the mean of two seeds, over the pixels of `mask` and
    all three channels: the signed and absolute mean differences, the standard error of the
    signed one (from the seed pairs' differences; pixels are independent), and the absolute
    difference that noise alone would leave (half the difference of the two pairs' differences,
    which has the variance of the difference of the means)."""
    n = int(mask.sum())
    a, b = (a1 + a2) / 2, (b1 + b2) / 2
    diff = (a - b)[mask]
    var = ((a1 - a2)[mask].mean(axis=-1) ** 2 + (b1 - b2)[mask].mean(axis=-1) ** 2) / 4
    stderr = math.sqrt(var.sum()) / n
    signed = float(diff.mean())
    # Where both renderers agree on 0 (mirror rays that all meet the backdrop), z is 0.
    z = signed / stderr if stderr > 1e-7 and abs(signed) > 1e-6 else 0.0
    return {"signed": signed, "stderr": stderr, "z": z,
            "abs": float(np.abs(diff).mean()),
            "abs_noise": float(np.abs(((a1 - a2) - (b1 - b2)) / 2)[mask].mean())}


def shot_stats(images, masks):
    stats = {}
    for region, mask in masks.items():
        if not mask.any():
            continue
        s = {"pixels": int(mask.sum())}
        for name, (x1, x2) in images.items():
            s[name] = float(((x1 + x2) / 2)[mask].mean())
            s[f"{name}_noise"] = float(np.abs(x1 - x2)[mask].mean() / 2)
        for label, a, b in PAIRS:
            s[label] = pair_stats(*images[a], *images[b], mask)
        stats[region] = s
    return stats


def table(title, stats):
    lines = [f"\n{title} (mean differences, z = difference / its standard error)",
             f"{'region':26} {'px':>5} {'lensray':>7} {'Mitsuba':>7} {'model':>7}  "
             + "  ".join(f"{label:>17}" for label, _, _ in PAIRS) + f"  {'|l-M|':>6} {'noise':>6}"]
    for region, s in stats.items():
        cells = "  ".join(f"{s[label]['signed']:+8.4f} ({s[label]['z']:+6.1f})"
                          for label, _, _ in PAIRS)
        lm = s["lensray - Mitsuba"]
        lines.append(f"{region:26} {s['pixels']:5d} {s['lensray']:7.4f} {s['mitsuba']:7.4f} "
                     f"{s['gltf']:7.4f}  {cells}  {lm['abs']:6.4f} {lm['abs_noise']:6.4f}")
    return "\n".join(lines)


def figure(path, rows, scale):
    """A PNG, one row per shot: lensray, Mitsuba, lensray - Mitsuba and lensray - lensray's
    model in Mitsuba, the differences times `scale` (red where lensray is brighter, blue where
    darker, grey 0)."""

    def signed(d):
        d = np.clip(d.mean(axis=-1) * scale, -1, 1)
        rgb = np.full(d.shape + (3,), 0.5)
        rgb[..., 0] += 0.5 * d
        rgb[..., 1] -= 0.5 * np.abs(d)
        rgb[..., 2] -= 0.5 * d
        return np.round(np.clip(rgb, 0, 1) * 255).astype(np.uint8)

    tiles = []
    for lensray, mitsuba, model in rows:
        gap = np.full((lensray.shape[0], 4, 3), 255, dtype=np.uint8)
        tiles.append(np.hstack([srgb8(lensray), gap, srgb8(mitsuba), gap,
                                signed(lensray - mitsuba), gap, signed(lensray - model)]))
    gap = np.full((4, tiles[0].shape[1], 3), 255, dtype=np.uint8)
    write_png(path, np.vstack([x for t in tiles for x in (t, gap)][:-1]))


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    p.add_argument("--lensray", required=True, help="lensray's release binary")
    p.add_argument("--out", required=True, help="work and results folder")
    p.add_argument("--width", type=int, default=160)
    p.add_argument("--height", type=int, default=120)
    p.add_argument("--spp", type=int, default=256, help="lensray's samples per pixel per seed")
    p.add_argument("--mitsuba-spp", type=int, default=256, help="Mitsuba's, per seed")
    p.add_argument("--roughness", type=float, default=0.3, help="the rough ball's glTF roughness")
    p.add_argument("--variant", default="llvm_ad_rgb",
                   help="Mitsuba variant (a JIT one: the glTF model is a Python BSDF)")
    args = p.parse_args()
    args.out = os.path.abspath(args.out)
    if "llvm" in args.variant and not os.environ.get("DRJIT_LIBLLVM_PATH"):
        found = sorted(glob.glob("/usr/lib/*-linux-gnu/libLLVM-19.so"))
        if found:
            os.environ["DRJIT_LIBLLVM_PATH"] = found[0]
    import mitsuba as mi
    mi.set_variant(args.variant)
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    import gltf_dielectric
    gltf_dielectric.register()
    write_scenes(args.out, args.roughness)

    # (name, lensray scene, roughness, bounces, backdrop). One bounce leaves the reflection at
    # the ball's front alone (F times what the mirrored ray meets); the furnace, the ball alone
    # under the sky, shows 1 wherever the glass loses nothing.
    r = args.roughness
    shots = [("smooth", "smooth", 0.0, BOUNCES, True), ("rough", "rough", r, BOUNCES, True),
             ("smooth, 1 bounce", "smooth", 0.0, 1, True), ("rough, 1 bounce", "rough", r, 1, True),
             ("smooth, furnace", "smooth-furnace", 0.0, BOUNCES, False),
             ("rough, furnace", "rough-furnace", r, BOUNCES, False)]
    seeds = (1, 2)
    renders, timings = {}, {}
    for name, scene, roughness, bounces, with_backdrop in shots:
        tag = name.replace(", ", "-").replace(" ", "")
        images = {}
        start = time.perf_counter()
        for seed in seeds:
            lensray_render(args, scene, bounces, seed, f"{args.out}/{tag}-lensray-{seed}.exr")
        images["lensray"] = [read_exr(mi, f"{args.out}/{tag}-lensray-{seed}.exr")
                             for seed in seeds]
        timings[f"{name}: lensray"] = time.perf_counter() - start
        for model in ("mitsuba", "gltf", "gltf-exact"):
            start = time.perf_counter()
            scene_m = mitsuba_scene(mi, args, model, roughness, bounces, with_backdrop)
            images[model] = []
            for seed in seeds:
                exr = f"{args.out}/{tag}-{model}-{seed}.exr"
                mi.Bitmap(mi.render(scene_m, spp=args.mitsuba_spp, seed=seed)).write(exr)
                images[model].append(read_exr(mi, exr))
            timings[f"{name}: {model}"] = time.perf_counter() - start
        renders[name] = images
        print(f"glass.py: rendered {name}", flush=True)

    # doubleSided false on the ball: the specification says it has no effect on a volume's
    # boundary, so this should render as the double-sided ball.
    single = f"{args.out}/smooth-single-sided-lensray-1.exr"
    lensray_render(args, "smooth-single-sided", BOUNCES, 1, single)
    single = read_exr(mi, single)

    masks = regions(args.width, args.height)
    results = {"settings": {k: v for k, v in vars(args).items() if k != "lensray"},
               "eye": EYE, "target": TARGET, "vfov": VFOV, "ior": IOR, "bounces": BOUNCES,
               "mitsuba_max_depth": BOUNCES + 1, "fresnel": fresnel_table(),
               "timings_s": timings, "shots": {}}
    report = []
    for name, images in renders.items():
        regions_here = masks if "furnace" not in name else {
            k: m for k, m in masks.items() if k.startswith("ball")}
        results["shots"][name] = shot_stats(images, regions_here)
        report.append(table(name, results["shots"][name]))

    # The camera: Mitsuba's smooth image moved by a pixel or mirrored, on the backdrop.
    a = sum(renders["smooth"]["lensray"]) / 2
    b = sum(renders["smooth"]["mitsuba"]) / 2
    m = masks["backdrop, far"]
    checks = {"as rendered": float(np.abs(a - b)[m].mean()),
              "Mitsuba mirrored": float(np.abs(a - b[:, ::-1])[m].mean())}
    for label, shift in (("Mitsuba 1 px right", (0, 1)), ("Mitsuba 1 px down", (1, 0))):
        checks[label] = float(np.abs(a - np.roll(b, shift, axis=(0, 1)))[m].mean())
    results["camera_check_backdrop_abs"] = checks
    ball = masks["ball interior (< 60 deg)"] | masks["ball rim (>= 60 deg)"]
    first = renders["smooth"]["lensray"]
    results["single_sided"] = {
        "ball_double_sided": float(a[ball].mean()),
        "ball_single_sided": float(single[ball].mean()),
        "ball_abs_diff": float(np.abs(single - first[0])[ball].mean()),
        "ball_abs_noise": float(np.abs(first[1] - first[0])[ball].mean()),
    }
    # Six decimals: under a tenth of each standard error (2e-5 and up; 1e-8 where both are black).
    rounded = lambda x: (round(x, 6) if isinstance(x, float) else  # noqa: E731
                         {k: rounded(v) for k, v in x.items()} if isinstance(x, dict) else
                         [rounded(v) for v in x] if isinstance(x, (list, tuple)) else x)
    with open(os.path.join(args.out, "results.json"), "w") as f:
        json.dump(rounded(results), f, indent=1)

    mean = lambda name, who: sum(renders[name][who]) / 2  # noqa: E731
    for name in renders:
        tag = name.replace(", ", "-").replace(" ", "")
        for who in ("lensray", "mitsuba", "gltf", "gltf-exact"):
            write_png(f"{args.out}/{tag}-{who}.png", srgb8(mean(name, who)))
    write_png(f"{args.out}/smooth-single-sided-lensray.png", srgb8(single))
    figure(f"{args.out}/glass.png", [(mean(k, "lensray"), mean(k, "mitsuba"), mean(k, "gltf"))
                                     for k in ("smooth", "rough", "rough, furnace")], scale=5.0)

    print("\nFresnel of index 1.5 from outside: angle, Schlick, exact")
    for row in results["fresnel"]:
        print(f"  {row['angle']:3d}  {row['schlick']:.4f}  {row['exact']:.4f}")
    print("\n".join(report))
    print("\ncamera check (mean |lensray - Mitsuba| on the far backdrop, smooth):",
          json.dumps({k: round(v, 4) for k, v in checks.items()}))
    print("doubleSided false:", json.dumps({k: round(v, 4)
                                           for k, v in results["single_sided"].items()}))
    print("seconds:", json.dumps({k: round(v, 1) for k, v in timings.items()}))
    print(f"\nresults: {args.out}/results.json; figure: {args.out}/glass.png")


if __name__ == "__main__":
    main()
