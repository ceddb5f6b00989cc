#!/usr/bin/env python3
"""Reference figures for lensray's built-in lenses from independent optics packages.

Needs: pip install rayoptics==0.9.8 optiland==0.6.3 opticalglass==1.1.1
(Python 3.11; scripts/optics/colour_reference.py, standard library only, for the cross-check)

    python scripts/optics/reference.py [--write-dline] [LENS ...]

For each lens of assets/lenses/ (or those named) it writes, in
crates/lensray/tests/lens_reference/:
  <lens>.colour.json  by ray-optics: efl and bfl at the F, d and C lines, the axial colour
                      (bfl_F - bfl_C) and the lateral colour (F minus C chief-ray height on
                      the d-line paraxial focal plane) at 5, 10, 15, 20 deg;
  <lens>.json         by ray-optics: the d-line figures of `lensray lens --json`, only where
                      the file is missing (`--write-dline` rewrites it); where it exists, the
                      figures are compared with it.
It prints the largest difference between ray-optics and the standard-library tracer
(colour_reference.py) on every figure, and for a lens with an asphere also recomputes the
d-line figures with optiland and prints the largest difference from ray-optics.

How the lens is modelled (the same in both packages): the prescription's rows as given; each
medium a constant index, the two-term Cauchy fit of issue 31 evaluated at the line's
wavelength (so one model per line); n_d alone where a row has no Abbe number. An asphere
(k=, a2=..a16=) becomes ray-optics' EvenPolynomial (coefs[0] multiplies r^2) or optiland's
even_asphere (coefficients[0] multiplies r^2); a2 must be 0 (neither package's paraxial
trace sees it). The stop fully open: the entrance pupil is the stop's paraxial image.
First-order figures come from the package's paraxial trace, the object at 1e10 mm
(ray-optics) or at infinity (optiland). Real rays (chief rays, LSA) start on a plane
2 x the widest clear aperture in front of the first vertex (as `lensray lens` does),
parallel, and are traced by the package; the chief ray's starting height is found by secant
steps on its traced height at the stop. A chief ray that any clear aperture blocks (the traced
points checked against the diameters) leaves its field out.
"""

import json
import math
import os
import sys
import warnings

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import colour_reference as stdlib  # noqa: E402  (the cross-check only)

warnings.filterwarnings("ignore")

# The lines, fields, heights, keys and folders are the stdlib tracer's: one definition.
from colour_reference import (  # noqa: E402
    ASPHERE_KEYS,
    FIELDS_DEG,
    LENS_DIR,
    LINES_NM,
    LSA_FRACTIONS,
    OUT_DIR,
)


def tool_rayoptics():
    import rayoptics

    return "ray-optics (rayoptics) %s, python %s" % (
        rayoptics.__version__, sys.version.split()[0])


def tool_optiland():
    from importlib.metadata import version

    return "optiland %s, python %s" % (version("optiland"), sys.version.split()[0])


# --- the prescription (read here again, not shared with the cross-check) ------------------


def read_rows(path):
    rows = []
    for line in open(path):
        fields = line.split("#", 1)[0].split()
        if not fields:
            continue
        plain = [f for f in fields if "=" not in f]
        row = dict(zip(("radius", "thickness", "nd", "diameter"), map(float, plain[:4])))
        row["nd"] = row["nd"] or 1.0
        row["vd"] = float(plain[4]) if len(plain) > 4 else None
        row.update({key: 0.0 for key in ASPHERE_KEYS})
        for f in fields:
            if "=" in f:
                key, value = f.split("=")
                assert key in ASPHERE_KEYS, f
                row[key] = float(value)
        rows.append(row)
    return rows


def index(row, wavelength_nm):
    """Issue 31's glass: n = A + B / l^2 through n_d and V_d at the d, F, C lines."""
    if row["nd"] == 1.0 or row["vd"] is None:
        return row["nd"]
    lf, ld, lc = LINES_NM["F"], LINES_NM["d"], LINES_NM["C"]
    b = (row["nd"] - 1.0) / (row["vd"] * (1.0 / lf ** 2 - 1.0 / lc ** 2))
    return row["nd"] - b / ld ** 2 + b / wavelength_nm ** 2


def is_asphere(row):
    return any(row[k] != 0.0 for k in ASPHERE_KEYS)


def coefficients(row):
    """[a2, a4, ..., a16], trailing zeros dropped."""
    c = [row["a%d" % n] for n in range(2, 17, 2)]
    while c and c[-1] == 0.0:
        c.pop()
    return c


def stop_of(rows):
    stops = [i for i, r in enumerate(rows) if r["radius"] == 0.0]
    assert len(stops) == 1
    return stops[0]


def start_distance(rows):
    return 2.0 * max(r["diameter"] for r in rows)


def secant(f, a, b, tol=1e-14, steps=60):
    fa, fb = f(a), f(b)
    for _ in range(steps):
        if fa is None or fb is None:
            return None
        if abs(fb) < tol or fb == fa:
            break
        a, fa, b = b, fb, b - fb * (b - a) / (fb - fa)
        fb = f(b)
    return b


# --- ray-optics ----------------------------------------------------------------------------


class RayOptics:
    """A prescription at one wavelength in ray-optics: a paraxial model (object at 1e10 mm)
    and a real-ray model (object plane at start_distance, image plane at `focus` from the
    last vertex)."""

    WVL = 587.56  # the media are constant: any wavelength traces the same

    def __init__(self, rows, wavelength_nm, focus=None):
        self.rows = rows
        self.n = [index(r, wavelength_nm) for r in rows]
        self.stop = stop_of(rows)
        for r in rows:
            if r["a2"] != 0.0:
                raise SystemExit("a2 != 0: ray-optics' paraxial trace would ignore it")
        # The stop's paraxial image for EPD 1, then the EPD that fills the stop.
        model = self.build(1e10, 1.0, None)
        ax = model["analysis_results"]["parax_data"].ax_ray
        h_stop = ax[self.stop + 1][0]
        self.epd = 0.5 * rows[self.stop]["diameter"] / abs(h_stop)
        model = self.build(1e10, self.epd, None)
        fod = model["analysis_results"]["parax_data"].fod
        model = self.build(1e10, self.epd, fod.bfl)
        self.paraxial = model
        self.fod = model["analysis_results"]["parax_data"].fod
        self.real = self.build(start_distance(rows), self.epd,
                               self.fod.bfl if focus is None else focus)

    def build(self, object_distance, epd, image_gap):
        from rayoptics.elem.profiles import EvenPolynomial
        from rayoptics.optical.opticalmodel import OpticalModel
        from rayoptics.raytr.opticalspec import FieldSpec, PupilSpec, WvlSpec

        opm = OpticalModel()
        sm, osp = opm["seq_model"], opm["optical_spec"]
        osp["pupil"] = PupilSpec(osp, key=["object", "epd"], value=epd)
        osp["fov"] = FieldSpec(osp, key=["object", "angle"], flds=[0.0, 1.0])
        osp["wvls"] = WvlSpec([(self.WVL, 1.0)], ref_wl=0)
        opm.radius_mode = True
        sm.gaps[0].thi = object_distance
        for i, (r, n) in enumerate(zip(self.rows, self.n)):
            t = r["thickness"] if i + 1 < len(self.rows) else (image_gap or 0.0)
            if r["radius"] == 0.0:
                sm.add_surface([0.0, t], sd=0.5 * r["diameter"])
                sm.set_stop()
            elif n == 1.0:
                sm.add_surface([r["radius"], t], sd=0.5 * r["diameter"])
            else:
                sm.add_surface([r["radius"], t, n], sd=0.5 * r["diameter"])
            if is_asphere(r):
                sm.ifcs[sm.cur_surface].profile = EvenPolynomial(
                    r=r["radius"], cc=r["k"], coefs=coefficients(r))
        opm.update_model()
        return opm

    def first_order(self):
        f = self.fod
        return {
            "efl_mm": f.efl,
            "bfl_mm": f.bfl,
            "ffl_mm": f.ffl,
            "front_principal_plane_mm": f.pp1,
            "rear_principal_plane_mm": f.ppk,
            "entrance_pupil": {"position_mm": f.enp_dist, "diameter_mm": 2.0 * f.enp_radius},
            "exit_pupil": {"position_mm": f.exp_dist, "diameter_mm": 2.0 * f.exp_radius},
            "f_number": f.efl / (2.0 * f.enp_radius),
        }

    def trace(self, y0, direction):
        """The ray's points at every interface (object plane first, image plane last) and
        the last direction; None when ray-optics cannot trace it."""
        from rayoptics.raytr import raytrace as rt
        from rayoptics.raytr.traceerror import TraceError

        try:
            ray, _, _ = rt.trace(self.real["seq_model"], np.array([0.0, y0, 0.0]),
                                 np.array(direction), self.WVL)
        except TraceError:
            return None
        return [seg[0] for seg in ray], ray[-1][1]

    def chief_ray(self, field_deg, guess):
        w = math.radians(field_deg)
        direction = (0.0, math.sin(w), math.cos(w))

        def at_stop(y0):
            out = self.trace(y0, direction)
            return None if out is None else out[0][self.stop + 1][1]

        y0 = (-start_distance(self.rows) - guess) * math.tan(w)
        y0 = secant(at_stop, y0, y0 + 1e-3)
        if y0 is None:
            return None
        out = self.trace(y0, direction)
        if out is None:
            return None
        points = out[0][1:-1]
        blocked = any(math.hypot(p[0], p[1]) > 0.5 * r["diameter"]
                      for p, r in zip(points, self.rows))
        return None if blocked else out[0][-1][1]

    def lsa(self, height):
        out = self.trace(height, (0.0, 0.0, 1.0))
        if out is None:
            return None
        p, d = out[0][-1], out[1]
        return p[2] - p[1] * d[2] / d[1]


def dline_rayoptics(rows):
    model = RayOptics(rows, LINES_NM["d"])
    out = model.first_order()
    guess = out["entrance_pupil"]["position_mm"]
    out["chief_ray"] = []
    for field in FIELDS_DEG:
        h = model.chief_ray(field, guess)
        if h is not None:
            out["chief_ray"].append({"field_deg": field, "image_height_mm": h})
    out["lsa"] = []
    for fraction in LSA_FRACTIONS:
        lsa = model.lsa(fraction * 0.5 * out["entrance_pupil"]["diameter_mm"])
        if lsa is not None:
            out["lsa"].append({"pupil_fraction": fraction, "lsa_mm": lsa})
    out["tool"] = tool_rayoptics()
    return out


def colour_rayoptics(rows):
    focus = RayOptics(rows, LINES_NM["d"]).fod.bfl
    models = {line: RayOptics(rows, nm, focus=focus) for line, nm in LINES_NM.items()}
    heights = {}
    for line in ("F", "C"):
        guess = models[line].fod.enp_dist
        heights[line] = {f: models[line].chief_ray(f, guess) for f in FIELDS_DEG}
    return {
        "efl_mm": {line: models[line].fod.efl for line in ("F", "d", "C")},
        "bfl_mm": {line: models[line].fod.bfl for line in ("F", "d", "C")},
        "axial_color_mm": models["F"].fod.bfl - models["C"].fod.bfl,
        "lateral_color": [
            {"field_deg": f, "lateral_color_mm": heights["F"][f] - heights["C"][f]}
            for f in FIELDS_DEG
            if heights["F"][f] is not None and heights["C"][f] is not None
        ],
        "wavelengths_nm": dict(LINES_NM),
        "tool": tool_rayoptics(),
    }


# --- optiland (the aspheric lenses' second opinion) -------------------------------------------


def dline_optiland(rows):
    import optiland.backend as be
    from optiland.materials import IdealMaterial
    from optiland.optic import Optic
    from optiland.rays import RealRays

    stop = stop_of(rows)
    for r in rows:
        if r["a2"] != 0.0:
            raise SystemExit("a2 != 0: optiland's paraxial trace would ignore it")
    n = [index(r, LINES_NM["d"]) for r in rows]
    op = Optic()
    op.surfaces.add(index=0, radius=be.inf, thickness=be.inf)
    for i, (r, ni) in enumerate(zip(rows, n)):
        kwargs = dict(
            index=i + 1,
            radius=r["radius"] if r["radius"] != 0.0 else be.inf,
            thickness=r["thickness"] if i + 1 < len(rows) else 0.0,
            material=IdealMaterial(ni),
            is_stop=i == stop,
        )
        if is_asphere(r):
            kwargs.update(surface_type="even_asphere", conic=r["k"],
                          coefficients=coefficients(r))
        op.surfaces.add(**kwargs)
    op.surfaces.add(index=len(rows) + 1)  # the image plane, at the last vertex
    op.set_aperture(aperture_type="EPD", value=1.0)
    op.fields.set_type(field_type="angle")
    op.fields.add(y=0.0)
    op.fields.add(y=1.0)
    op.wavelengths.add(value=LINES_NM["d"] / 1000.0, is_primary=True)
    # The EPD that fills the stop: the paraxial marginal ray's height there.
    y, _ = op.paraxial.marginal_ray()
    h_stop = float(np.ravel(be.to_numpy(y))[stop + 1])
    op.set_aperture(aperture_type="EPD", value=0.5 * rows[stop]["diameter"] / abs(h_stop))
    p = op.paraxial
    num = lambda v: float(np.ravel(be.to_numpy(v))[0])  # noqa: E731
    efl = num(p.f2())
    out = {
        "efl_mm": efl,
        "bfl_mm": num(p.F2()),
        "ffl_mm": num(p.F1()),
        "front_principal_plane_mm": num(p.P1()),
        "rear_principal_plane_mm": num(p.P2()),
        "entrance_pupil": {"position_mm": num(p.EPL()), "diameter_mm": num(p.EPD())},
        "exit_pupil": {"position_mm": num(p.XPL()), "diameter_mm": num(p.XPD())},
    }
    out["f_number"] = efl / out["entrance_pupil"]["diameter_mm"]
    last_z = sum(r["thickness"] for r in rows[:-1])
    focus_z = last_z + out["bfl_mm"]
    z0 = -start_distance(rows)
    sg = op.surface_group

    def trace(y0, direction):
        rays = RealRays(0.0, y0, z0, direction[0], direction[1], direction[2], 1.0,
                        LINES_NM["d"] / 1000.0)
        sg.trace(rays, skip=1)  # records the traced surfaces only: [k] is row k
        pts = [(float(sg.x[i][0]), float(sg.y[i][0]), float(sg.z[i][0]))
               for i in range(len(rows))]
        last = len(rows) - 1
        d = (float(sg.L[last][0]), float(sg.M[last][0]), float(sg.N[last][0]))
        if any(not math.isfinite(c) for p_ in pts for c in p_):
            return None
        return pts, d

    out["chief_ray"] = []
    for field in FIELDS_DEG:
        w = math.radians(field)
        direction = (0.0, math.sin(w), math.cos(w))

        def at_stop(y0):
            t = trace(y0, direction)
            return None if t is None else t[0][stop][1]

        y0 = (z0 - out["entrance_pupil"]["position_mm"]) * math.tan(w)
        y0 = secant(at_stop, y0, y0 + 1e-3, tol=1e-12)
        t = None if y0 is None else trace(y0, direction)
        if t is None:
            continue
        pts, d = t
        if any(math.hypot(q[0], q[1]) > 0.5 * r["diameter"] for q, r in zip(pts, rows)):
            continue
        q = pts[-1]
        out["chief_ray"].append({"field_deg": field,
                                 "image_height_mm": q[1] + (focus_z - q[2]) * d[1] / d[2]})
    out["lsa"] = []
    for fraction in LSA_FRACTIONS:
        t = trace(fraction * 0.5 * out["entrance_pupil"]["diameter_mm"], (0.0, 0.0, 1.0))
        if t is None:
            continue
        q, d = t[0][-1], t[1]
        out["lsa"].append({"pupil_fraction": fraction,
                           "lsa_mm": q[2] - q[1] * d[2] / d[1] - focus_z})
    out["tool"] = tool_optiland()
    return out


# --- main ------------------------------------------------------------------------------------


def write_json(path, data):
    with open(path, "w") as f:
        json.dump(data, f, indent=2)
        f.write("\n")


def main(argv):
    write_dline = "--write-dline" in argv
    names = [a for a in argv if not a.startswith("--")] or stdlib.lens_names()
    worst = {"colour": 0.0, "dline": 0.0, "optiland": 0.0}
    for name in names:
        rows = read_rows(os.path.join(LENS_DIR, name + ".dat"))
        colour = colour_rayoptics(rows)
        write_json(os.path.join(OUT_DIR, name + ".colour.json"), colour)
        dline = dline_rayoptics(rows)
        path = os.path.join(OUT_DIR, name + ".json")
        if os.path.exists(path) and not write_dline:
            with open(path) as f:
                stored = json.load(f)
            diff, key, odd = stdlib.largest_difference(dline, stored)
            print("%-18s d line vs the stored %s: %.1e mm (%s)%s" % (
                name, os.path.basename(path), diff, key, " odd keys %s" % odd if odd else ""))
        else:
            write_json(path, dline)
            print("%-18s wrote %s" % (name, os.path.basename(path)))
        srows = stdlib.read_lens(os.path.join(LENS_DIR, name + ".dat"))
        s_colour, _ = stdlib.colour_data(srows)
        s_dline, _ = stdlib.dline_data(srows)
        for what, a, b in (("colour", colour, s_colour), ("dline", dline, s_dline)):
            diff, key, odd = stdlib.largest_difference(a, b)
            worst[what] = max(worst[what], diff)
            print("%-18s %s: ray-optics vs stdlib tracer %.1e mm (%s)%s" % (
                "", what, diff, key, " ODD KEYS %s" % odd if odd else ""))
        print("%-18s axial colour %+.6f mm, efl F/d/C %.6f %.6f %.6f" % (
            "", colour["axial_color_mm"], *(colour["efl_mm"][k] for k in "FdC")))
        if any(is_asphere(r) for r in rows):
            opt = dline_optiland(rows)
            diff, key, odd = stdlib.largest_difference(dline, opt)
            worst["optiland"] = max(worst["optiland"], diff)
            print("%-18s d line: ray-optics vs optiland %.1e mm (%s)%s" % (
                "", diff, key, " ODD KEYS %s" % odd if odd else ""))
            diff, key, _ = stdlib.largest_difference(opt, s_dline)
            print("%-18s d line: optiland vs stdlib tracer %.1e mm (%s)" % ("", diff, key))
    print("largest ray-optics vs stdlib difference: colour %.1e mm, d line %.1e mm; "
          "ray-optics vs optiland (aspheric lenses) %.1e mm" % (
              worst["colour"], worst["dline"], worst["optiland"]))


if __name__ == "__main__":
    main(sys.argv[1:])
