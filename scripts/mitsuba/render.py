#!/usr/bin/env python3
"""lensray's shots in Mitsuba 3 (`llvm_ad_rgb`: Embree + Dr.Jit's LLVM back end).

Subcommands (scripts/mitsuba/compare.sh drives them; docs/mitsuba.md explains the method):

  export OBJ OUT_DIR   the OBJ that `lensray generate` writes -> one binary PLY per material
                       (positions, normals) and materials.json; skipped when up to date.
  time                 loads the exported scene with the camera of a `lensray bench --json` file,
                       renders once untimed (JIT), then --runs timed renders; prints one JSON line.
  diff A B             mean absolute difference of two linear RGB images (EXR), and of B shifted by
                       a pixel, as a check of framing.

Mitsuba is imported only by `time` and `diff`, after DRJIT_LIBLLVM_PATH is set by the caller.
"""

import argparse
import json
import os
import statistics
import sys
import time
import tomllib

import numpy as np

# --- export ---------------------------------------------------------------------------------


def read_mtl(path):
    """Material name -> Kd (linear RGB) of a lensray MTL file."""
    kd, name = {}, None
    with open(path) as f:
        for line in f:
            parts = line.split()
            if parts[:1] == ["newmtl"]:
                name = parts[1]
            elif parts[:1] == ["Kd"] and name is not None:
                kd[name] = [float(x) for x in parts[1:4]]
    return kd


def read_obj(path):
    """Positions, normals (or None) and {material: (N, 3) zero-based corner indices} of an OBJ
    as `lensray generate` writes it: `v`, `vn`, `usemtl`, and `f a b c` or `f a//a b//b c//c`
    triangles whose normal index equals the position index."""
    with open(path, "rb") as f:
        lines = f.read().split(b"\n")
    v, vn, faces, current = [], [], {}, None
    for line in lines:
        head = line[:2]
        if head == b"v ":
            v.append(line[2:])
        elif head == b"vn":
            vn.append(line[3:])
        elif head == b"f ":
            faces[current].append(line[2:])
        elif line.startswith(b"usemtl "):
            current = line[7:].strip().decode()
            faces.setdefault(current, [])
    positions = np.array(b" ".join(v).split(), dtype=np.float32).reshape(-1, 3)
    normals = np.array(b" ".join(vn).split(), dtype=np.float32).reshape(-1, 3) if vn else None
    if normals is not None and len(normals) != len(positions):
        sys.exit(f"{path}: {len(normals)} normals for {len(positions)} positions")
    indices = {}
    for name, rows in faces.items():
        text = b" ".join(rows).replace(b"//", b" ")
        flat = np.array(text.split(), dtype=np.int64)
        per_face = flat.size // len(rows)
        if per_face not in (3, 6):
            sys.exit(f"{path}: faces of material {name} are not triangles")
        corners = flat.reshape(len(rows), per_face)[:, :: per_face // 3]
        indices[name] = corners - 1
    return positions, normals, indices


def write_ply(path, positions, normals, triangles):
    """Binary little-endian PLY: float x y z [nx ny nz], faces as uchar-counted uint32 lists."""
    fields = ["x", "y", "z"] + (["nx", "ny", "nz"] if normals is not None else [])
    vertex = np.hstack([positions] + ([normals] if normals is not None else [])).astype("<f4")
    face = np.empty(len(triangles), dtype=[("n", "u1"), ("i", "<u4", (3,))])
    face["n"], face["i"] = 3, triangles
    header = ["ply", "format binary_little_endian 1.0", f"element vertex {len(vertex)}"]
    header += [f"property float {name}" for name in fields]
    header += [f"element face {len(face)}", "property list uchar uint vertex_indices", "end_header"]
    tmp = path + ".tmp"
    with open(tmp, "wb") as f:
        f.write(("\n".join(header) + "\n").encode())
        f.write(np.ascontiguousarray(vertex).tobytes())
        f.write(face.tobytes())
    os.replace(tmp, path)


def export(obj, out_dir):
    """The OBJ as one PLY per material (each with only its own vertices) and materials.json,
    unless materials.json already records this OBJ's size and modification time."""
    stamp = {"obj": os.path.abspath(obj), "size": os.path.getsize(obj),
             "mtime_ns": os.stat(obj).st_mtime_ns}
    manifest = os.path.join(out_dir, "materials.json")
    if os.path.exists(manifest):
        with open(manifest) as f:
            if json.load(f).get("source") == stamp:
                print(f"{out_dir}: up to date")
                return
    start = time.perf_counter()
    kd = read_mtl(os.path.splitext(obj)[0] + ".mtl")
    positions, normals, indices = read_obj(obj)
    os.makedirs(out_dir, exist_ok=True)
    shapes, total = [], 0
    for name, corners in indices.items():
        used, local = np.unique(corners, return_inverse=True)
        file = f"{name}.ply"
        write_ply(os.path.join(out_dir, file), positions[used],
                  None if normals is None else normals[used], local.reshape(-1, 3))
        shapes.append({"file": file, "material": name, "kd": kd[name], "triangles": len(corners)})
        total += len(corners)
    with open(os.path.splitext(obj)[0] + ".toml", "rb") as f:
        settings = tomllib.load(f)
    lights = settings.get("light", [])
    lights = [lights] if isinstance(lights, dict) else lights
    # Only point lights with position and intensity given translate (the generated scenes').
    lights = [{"position": light["position"], "intensity": light["intensity"]}
              for light in lights if light.get("type", "point") == "point"
              and "position" in light and "intensity" in light and "range" not in light]
    background = settings.get("render", {}).get("background", [0.0, 0.0, 0.0])
    with open(manifest, "w") as f:
        json.dump({"source": stamp, "triangles": total, "background": background,
                   "lights": lights, "shapes": shapes}, f, indent=1)
    print(f"wrote {len(shapes)} PLY files ({total} triangles) to {out_dir} "
          f"in {time.perf_counter() - start:.1f} s")


# --- the Mitsuba scene ------------------------------------------------------------------------


def register_unlit(mi, dr):
    """`unlit`: lensray's unlit shading. One camera ray, its closest hit with the fewest
    surface quantities (RayFlags.Minimal: no UVs, shading frame or derivatives),
    the hit shape's diffuse colour, the background on a miss."""

    class Unlit(mi.SamplingIntegrator):
        def __init__(self, props):
            super().__init__(props)
            self.background = mi.Color3f(props.get("background", mi.ScalarColor3f(0.0)))

        def sample(self, scene, sampler, ray, medium=None, active=True, **_):
            si = scene.ray_intersect(ray, ray_flags=mi.RayFlags.Minimal, coherent=True,
                                     active=active)
            hit = si.is_valid()
            albedo = si.bsdf(ray).eval_diffuse_reflectance(si, hit)
            return dr.select(hit, albedo, self.background), mi.Bool(True), []

        def aov_names(self):
            return []

    mi.register_integrator("unlit", lambda props: Unlit(props))


def integrator(kind, background):
    """The integrator dictionary of `kind` (see docs/mitsuba.md for the choice)."""
    if kind == "unlit":
        return {"type": "unlit", "background": background}
    if kind == "aov":
        # The albedo AOV: a full surface interaction per hit (UVs, frames), black on a miss.
        return {"type": "aov", "aovs": "albedo:albedo"}
    if kind == "lit":
        # Direct light from the point light: one shadow ray per hit, as lensray's `lit` with
        # one light and no environment; black on a miss.
        return {"type": "direct", "emitter_samples": 1, "bsdf_samples": 0}
    sys.exit(f"unknown integrator {kind}")


def sensor(mi, camera, spp):
    """A thin-lens sensor framing exactly what lensray's camera frames (docs/mitsuba.md)."""
    if camera["projection"] != "perspective":
        sys.exit("only perspective cameras are translated")
    if camera["lens"] != "thin" or camera["aperture"] != "round":
        sys.exit("only a round thin lens (or a pinhole) is translated")
    to_world = mi.ScalarTransform4f().look_at(
        origin=camera["eye"], target=camera["target"], up=camera["up"])
    pinhole = camera["aperture_radius"] == 0.0
    s = {
        "type": "perspective" if pinhole else "thinlens",
        "fov": camera["vfov_degrees"],
        "fov_axis": "y",
        # lensray's perspective rays start at the lens, unclipped: no near plane in effect.
        "near_clip": 1e-6,
        "far_clip": 1e7,
        "to_world": to_world,
        "film": {
            "type": "hdrfilm", "width": camera["width"], "height": camera["height"],
            "rfilter": {"type": "box"}, "pixel_format": "rgb", "component_format": "float32",
        },
        "sampler": {"type": "independent", "sample_count": spp},
    }
    if not pinhole:
        s["aperture_radius"] = camera["aperture_radius"]
        s["focus_distance"] = camera["focus_distance"]
    return s


def scene_dict(mi, args, camera, manifest):
    """The Mitsuba scene: `export`'s shapes, each with its diffuse colour, the camera, the
    integrator and (lit) the scene file's point lights."""
    scene = {"type": "scene", "sensor": sensor(mi, camera, args.spp),
             "integrator": integrator(args.integrator, manifest["background"])}
    for i, shape in enumerate(manifest["shapes"]):
        scene[f"shape_{i}"] = {
            "type": "ply", "filename": os.path.join(args.scene, shape["file"]),
            "bsdf": {"type": "diffuse", "reflectance": {"type": "rgb", "value": shape["kd"]}},
        }
    if args.integrator == "lit":
        if not manifest["lights"]:
            sys.exit("lit: the scene file names no point light")
        for i, light in enumerate(manifest["lights"]):
            scene[f"light_{i}"] = {"type": "point", "position": light["position"],
                                   "intensity": {"type": "rgb", "value": light["intensity"]}}
    return scene


# --- time -------------------------------------------------------------------------------------


class EmbreeLog:
    """Reads the Embree build time from Mitsuba's log ("Embree ready. (took 15ms)")."""

    def __init__(self, mi):
        self.seconds = None
        log = self

        class Appender(mi.Appender):
            def append(self, level, text):
                if "Embree ready" in text and "took" in text:
                    log.seconds = parse_duration(text.rsplit("took", 1)[1].strip(" )."))
                if level >= mi.LogLevel.Warn:
                    print(text, file=sys.stderr)

            def log_progress(self, *_):
                pass

        mi.logger().clear_appenders()
        mi.logger().add_appender(Appender())
        mi.set_log_level(mi.LogLevel.Info)


def parse_duration(text):
    """Mitsuba's time strings: "15ms", "1.2s", "350us"."""
    for unit, scale in (("ms", 1e-3), ("us", 1e-6), ("ns", 1e-9), ("s", 1.0), ("m", 60.0)):
        if text.endswith(unit):
            try:
                return float(text[: -len(unit)]) * scale
            except ValueError:
                return None
    return None


def render_once(mi, dr, scene, spp, seed):
    """One render, evaluated: (wall seconds of the call, seconds Dr.Jit's kernel history gives
    its kernels' execution, seconds of LLVM code generation and compilation, the image)."""
    dr.kernel_history()  # drop what came before
    start = time.perf_counter()
    image = mi.render(scene, spp=spp, seed=seed)
    dr.eval(image)
    dr.sync_thread()
    wall = time.perf_counter() - start
    kernels = dr.kernel_history()
    execution = sum(k.get("execution_time", 0.0) for k in kernels) * 1e-3
    compile_ = sum(k.get("codegen_time", 0.0) + k.get("backend_time", 0.0) for k in kernels) * 1e-3
    return wall, execution, compile_, image


def time_shot(args):
    start = time.perf_counter()
    import drjit as dr
    import mitsuba as mi
    mi.set_variant("llvm_ad_rgb")
    dr.set_thread_count(args.threads)
    dr.set_flag(dr.JitFlag.KernelHistory, True)
    imported = time.perf_counter() - start
    embree = EmbreeLog(mi)
    register_unlit(mi, dr)
    with open(args.camera) as f:
        camera = json.load(f)["camera"]
    if args.size:
        camera["width"], camera["height"] = (int(x) for x in args.size.split("x"))
    with open(os.path.join(args.scene, "materials.json")) as f:
        manifest = json.load(f)
    start = time.perf_counter()
    scene = mi.load_dict(scene_dict(mi, args, camera, manifest))
    load = time.perf_counter() - start
    first = render_once(mi, dr, scene, args.spp, 0)
    runs = [render_once(mi, dr, scene, args.spp, seed) for seed in range(1, args.runs + 1)]
    if args.exr or args.png:
        # The timed renders have seeds 1..runs: their mean is one image at runs x spp.
        mean = sum(np.array(r[3], dtype=np.float64) for r in runs) / len(runs)
        for path in filter(None, (args.exr, args.png)):
            mi.util.write_bitmap(path, mi.TensorXf(mean.astype(np.float32)))
    walls = sorted(r[0] for r in runs)
    median = statistics.median(walls)
    rays = camera["width"] * camera["height"] * args.spp
    result = {
        "renderer": f"mitsuba {mi.__version__} llvm_ad_rgb", "integrator": args.integrator,
        "threads": dr.thread_count(), "width": camera["width"], "height": camera["height"],
        "spp": args.spp, "triangles": manifest["triangles"], "camera_rays": rays,
        "import_seconds": imported, "load_seconds": load, "embree_seconds": embree.seconds,
        "first_render_seconds": first[0], "first_render_compile_seconds": first[2],
        "render_seconds": [r[0] for r in runs], "kernel_seconds": [r[1] for r in runs],
        "median_render_seconds": median, "mrays_per_second": rays / median / 1e6,
    }
    print(json.dumps(result))


# --- diff -------------------------------------------------------------------------------------


def read_linear(mi, path):
    image = np.array(mi.Bitmap(path).convert(mi.Bitmap.PixelFormat.RGB, mi.Struct.Type.Float32,
                                             srgb_gamma=False))
    return image.astype(np.float64)


def diff(args):
    import mitsuba as mi
    mi.set_variant("scalar_rgb")
    a, b = read_linear(mi, args.a), read_linear(mi, args.b)
    if a.shape != b.shape:
        sys.exit(f"{args.a} is {a.shape}, {args.b} is {b.shape}")
    result = {"mean_abs_diff": float(np.abs(a - b).mean()), "mean_a": float(a.mean()),
              "mean_b": float(b.mean())}
    for name, (dy, dx) in {"right": (0, 1), "left": (0, -1), "down": (1, 0), "up": (-1, 0)}.items():
        # B moved by one pixel, compared where both are defined.
        shifted = np.roll(b, (dy, dx), axis=(0, 1))[1:-1, 1:-1]
        result[f"mean_abs_diff_b_shifted_{name}"] = float(np.abs(a[1:-1, 1:-1] - shifted).mean())
    result["mean_abs_diff_b_mirrored"] = float(np.abs(a - b[:, ::-1]).mean())
    print(json.dumps(result))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    sub = parser.add_subparsers(dest="command", required=True)
    p = sub.add_parser("export")
    p.add_argument("obj")
    p.add_argument("out_dir")
    p = sub.add_parser("time")
    p.add_argument("--scene", required=True, help="a folder `export` wrote")
    p.add_argument("--camera", required=True, help="a `lensray bench --json` file")
    p.add_argument("--size", help="WxH instead of the camera's")
    p.add_argument("--integrator", choices=["unlit", "aov", "lit"], default="unlit")
    p.add_argument("--threads", type=int, default=os.cpu_count())
    p.add_argument("--spp", type=int, default=16)
    p.add_argument("--runs", type=int, default=5)
    p.add_argument("--exr", help="write the mean of the timed renders (linear)")
    p.add_argument("--png", help="the same, sRGB")
    p = sub.add_parser("diff")
    p.add_argument("a")
    p.add_argument("b")
    args = parser.parse_args()
    if args.command == "export":
        export(args.obj, args.out_dir)
    elif args.command == "time":
        time_shot(args)
    else:
        diff(args)


if __name__ == "__main__":
    main()
