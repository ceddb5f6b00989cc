"""Mitsuba 3's figures for lensray's rough-slab white furnace (crates/lensray-core/tests/reference/
glass.rs: a_rough_glass_slab_in_a_white_furnace_loses_what_mitsuba_finds): a 3 x 3 x 0.2 slab of
index 1.5 and glTF roughness 0.3 under a uniform white sky, seen from 3 units away face-on and 60
degrees off its normal through a window 0.2 units to each side of its centre, 16 x 16 pixels,
17 vertices a path (lensray's 16 surfaces), no Russian roulette. Prints the mean of each render
(two seeds of 4096 samples) with lensray's model (gltf_dielectric.py) and Mitsuba's
roughdielectric (GGX, alpha 0.09). Run through slab.sh."""
import math
import os
import sys

import mitsuba as mi
import numpy as np

mi.set_variant("llvm_ad_rgb")
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import gltf_dielectric  # noqa: E402

gltf_dielectric.register()

BSDFS = {
    "lensray's model": {"type": "gltf_dielectric", "ior": 1.5, "roughness": 0.3},
    "roughdielectric": {"type": "roughdielectric", "distribution": "ggx", "alpha": 0.09,
                        "int_ior": 1.5, "ext_ior": 1.0},
}

for name, bsdf in BSDFS.items():
    for degrees in (0.0, 60.0):
        s, c = math.sin(math.radians(degrees)), math.cos(math.radians(degrees))
        look = mi.ScalarTransform4f().look_at(origin=[3 * s, 0, 3 * c], target=[0, 0, 0],
                                              up=[0, 1, 0])
        scene = mi.load_dict({
            "type": "scene",
            "integrator": {"type": "path", "max_depth": 17, "rr_depth": 1000},
            "sensor": {"type": "perspective", "fov_axis": "y", "to_world": look,
                       "fov": 2 * math.degrees(math.atan(0.2 / 3.0)),
                       "film": {"type": "hdrfilm", "width": 16, "height": 16,
                                "rfilter": {"type": "box"}},
                       "sampler": {"type": "independent", "sample_count": 4096}},
            "emitter": {"type": "constant", "radiance": {"type": "rgb", "value": 1.0}},
            "slab": {"type": "cube", "bsdf": bsdf,
                     "to_world": mi.ScalarTransform4f().scale([1.5, 1.5, 0.1])},
        })
        means = [float(np.array(mi.render(scene, seed=seed)).mean()) for seed in (1, 2)]
        print(f"{name}, {degrees:.0f} degrees: {sum(means) / 2:.4f} "
              f"(seeds {means[0]:.4f}, {means[1]:.4f})", flush=True)
