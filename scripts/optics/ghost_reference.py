#!/usr/bin/env python3
"""Ghost paths through a lens by the independent standard-library tracer
(colour_reference.py's sphere and asphere intersections, vector Snell's law), for
lensray-core's tests/ghosts.rs: the real chief ray at 5 and 10 degrees, reflected by surface j,
back to surface i, reflected again and on to the paraxial focal plane, for every pair of
refracting surfaces (i < j) whose ghost path no clear aperture or stop blocks, at the d line.
Writes crates/lensray-core/tests/optics_reference/ghosts.stdlib.json.

    python3 scripts/optics/ghost_reference.py [LENS ...]   (default: double-gauss-50)
"""
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from colour_reference import LENS_DIR, LINES_NM, ROOT, Lens, read_lens  # noqa: E402

OUT = os.path.join(ROOT, "crates", "lensray-core", "tests", "optics_reference", "ghosts.stdlib.json")
FIELDS_DEG = [5.0, 10.0]


def reflect(lens, i, o, d):
    """(origin, direction) reflected by surface i; None if missed, clipped, or the stop."""
    if lens.rows[i]["radius"] == 0.0:
        return None
    met = lens.meet(i, o, d, clip=True)
    if met is None:
        return None
    p, n = met
    dn = d[0] * n[0] + d[1] * n[1] + d[2] * n[2]
    return p, (d[0] - 2 * dn * n[0], d[1] - 2 * dn * n[1], d[2] - 2 * dn * n[2])


def ghost(lens, o, d, i, j):
    out = lens.trace(o, d, 0, j, clip=True)
    if out is None:
        return None
    out = reflect(lens, j, *out)
    for s in reversed(range(i + 1, j)):
        if out is None:
            return None
        out = lens.pass_surface(s, *out, clip=True, backward=True)
    if out is None:
        return None
    out = reflect(lens, i, *out)
    if out is None:
        return None
    return lens.trace(out[0], out[1], i + 1, len(lens.rows), clip=True)


def lens_ghosts(name):
    lens = Lens(read_lens(os.path.join(LENS_DIR, name + ".dat")), LINES_NM["d"])
    first = lens.first_order()
    plane = lens.length + first["bfl_mm"]
    rays = []
    for field in FIELDS_DEG:
        chief = lens.chief_ray(field, first["entrance_pupil"]["position_mm"])
        o, d = chief
        ghosts = []
        surfaces = [s for s in range(len(lens.rows)) if lens.rows[s]["radius"] != 0.0]
        for a in range(len(surfaces)):
            for b in range(a + 1, len(surfaces)):
                i, j = surfaces[a], surfaces[b]
                out = ghost(lens, o, d, i, j)
                if out is None:
                    continue
                (po, pd) = out
                t = (plane - po[2]) / pd[2]
                ghosts.append({"i": i, "j": j, "x_mm": po[0] + t * pd[0], "y_mm": po[1] + t * pd[1]})
        rays.append({"field_deg": field, "origin": list(o), "direction": list(d), "ghosts": ghosts})
    return {"plane_z_mm": plane, "rays": rays}


def main(argv):
    names = argv[1:] or ["double-gauss-50"]
    data = {"tool": "independent stdlib Python tracer (scripts/optics/ghost_reference.py)",
            "lenses": {name: lens_ghosts(name) for name in names}}
    with open(OUT, "w") as f:
        json.dump(data, f, indent=1)
        f.write("\n")
    for name, lens in data["lenses"].items():
        print(name, [len(r["ghosts"]) for r in lens["rays"]], "ghosts at", FIELDS_DEG, "deg")


if __name__ == "__main__":
    main(sys.argv)
