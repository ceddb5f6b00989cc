#!/usr/bin/env python3
"""Reference figures for lensray's built-in lenses from a small tracer in standard-library
Python only (no numpy, no optics package): the cross-check of `reference.py` (rayoptics).

Needs: Python 3.8 or later, nothing else.

    python3 scripts/optics/colour_reference.py [LENS ...]

For each lens in assets/lenses/ (or those named) it writes, in
crates/lensray/tests/lens_reference/:
  <lens>.colour.stdlib.json  efl and bfl at the F, d and C lines, the axial colour and the
                             lateral colour (the keys of <lens>.colour.json);
  <lens>.stdlib.json         the d-line figures of `lensray lens --json` (the keys of
                             <lens>.json), only where the file is missing; where it exists the
                             figures are compared with it and the largest difference printed
                             (`--write-dline` rewrites it).

Definitions (those of crates/lensray-core/src/optics/analysis.rs and issue 31):
- Prescription rows: radius, thickness, n_d, clear-aperture diameter, optional V_d, optional
  `k=` and `a2=`..`a16=` (even asphere: z = c r^2 / (1 + sqrt(1 - (1 + k) c^2 r^2)) + sum
  a_n r^n, c = 1 / radius, + toward the film). Radius 0 is the aperture stop.
- Glass: two-term Cauchy fit through the d, F and C lines, n(l) = A + B / l^2 with
  B = (n_d - 1) / (V_d (l_F^-2 - l_C^-2)) and A = n_d - B / l_d^2; l_d = 587.56 nm,
  l_F = 486.13 nm, l_C = 656.27 nm. A glass row without V_d keeps n_d at every wavelength.
- Paraxial: y-nu trace (ABCD matrices on (y, n u)); an asphere's paraxial curvature is
  c + 2 a2.
- Chief ray at field angle w: the real ray (exact sphere / asphere intersection, vector
  Snell's law) that crosses the stop's plane on the axis, found by secant steps on its
  starting height; its height where it meets the d-line paraxial focal plane. A field is
  left out when a clear aperture blocks the chief ray (as `lensray lens` does).
- Axial colour: bfl_F - bfl_C. Lateral colour: F chief ray height minus C chief ray height,
  both on the d-line paraxial focal plane, each ray aimed at its own wavelength.
"""

import json
import math
import os
import sys

LINES_NM = {"F": 486.13, "d": 587.56, "C": 656.27}
FIELDS_DEG = [5.0, 10.0, 15.0, 20.0]
LSA_FRACTIONS = [0.25, 0.5, 0.75, 1.0]
ASPHERE_KEYS = ["k"] + ["a%d" % n for n in range(2, 17, 2)]

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
LENS_DIR = os.path.join(ROOT, "assets", "lenses")
OUT_DIR = os.path.join(ROOT, "crates", "lensray", "tests", "lens_reference")
TOOL = "independent stdlib Python tracer (scripts/optics/colour_reference.py)"


# --- prescription ------------------------------------------------------------------------


def read_lens(path):
    """The rows of a prescription file: a list of dicts (radius, thickness, nd, diameter,
    vd or None, k, a2..a16)."""
    rows = []
    with open(path) as f:
        for line in f:
            content = line.split("#", 1)[0].split()
            if not content:
                continue
            numbers = [x for x in content if "=" not in x]
            keywords = [x for x in content if "=" in x]
            if len(numbers) not in (4, 5):
                raise ValueError("%s: bad row %r" % (path, line))
            radius, thickness, nd, diameter = (float(x) for x in numbers[:4])
            row = {
                "radius": radius,
                "thickness": thickness,
                "nd": 1.0 if nd == 0.0 else nd,
                "diameter": diameter,
                "vd": float(numbers[4]) if len(numbers) == 5 else None,
            }
            for key in ASPHERE_KEYS:
                row[key] = 0.0
            for kw in keywords:
                key, value = kw.split("=", 1)
                if key not in ASPHERE_KEYS:
                    raise ValueError("%s: unknown field %r" % (path, kw))
                if radius == 0.0:
                    raise ValueError("%s: the stop cannot be an asphere" % path)
                row[key] = float(value)
            rows.append(row)
    return rows


def cauchy(nd, vd, wavelength_nm):
    """The index at `wavelength_nm` of the two-term Cauchy glass through n_d and V_d."""
    if nd == 1.0 or vd is None:
        return nd
    lf, ld, lc = LINES_NM["F"], LINES_NM["d"], LINES_NM["C"]
    b = (nd - 1.0) / (vd * (lf ** -2 - lc ** -2))
    a = nd - b / ld ** 2
    return a + b / wavelength_nm ** 2


class Lens:
    """A prescription at one wavelength: vertices, indices, shapes."""

    def __init__(self, rows, wavelength_nm):
        self.rows = rows
        self.n_after = [cauchy(r["nd"], r["vd"], wavelength_nm) for r in rows]
        self.n_before = [1.0] + self.n_after[:-1]
        self.z = []
        z = 0.0
        for r in rows:
            self.z.append(z)
            z += r["thickness"]
        self.length = self.z[-1]
        stops = [i for i, r in enumerate(rows) if r["radius"] == 0.0]
        assert len(stops) == 1, "one stop"
        self.stop = stops[0]

    # --- paraxial ---

    def paraxial_curvature(self, i):
        r = self.rows[i]
        c = 0.0 if r["radius"] == 0.0 else 1.0 / r["radius"]
        return c + 2.0 * r["a2"]

    def matrix(self, start, end):
        """ABCD on (y, n u) from just before surface `start` to just after `end - 1`."""
        a, b, c, d = 1.0, 0.0, 0.0, 1.0
        for i in range(start, end):
            if i > start:
                t = self.rows[i - 1]["thickness"] / self.n_after[i - 1]
                a, b = a + t * c, b + t * d
            power = (self.n_after[i] - self.n_before[i]) * self.paraxial_curvature(i)
            a, b, c, d = a, b, c - power * a, d - power * b
        return a, b, c, d

    def first_order(self):
        a, b, c, d = self.matrix(0, len(self.rows))
        efl = -1.0 / c
        out = {
            "efl_mm": efl,
            "bfl_mm": -a / c,
            "ffl_mm": d / c,
            "front_principal_plane_mm": (d - 1.0) / c,
            "rear_principal_plane_mm": (1.0 - a) / c,
        }
        stop = self.stop
        stop_d = self.rows[stop]["diameter"]
        if stop == 0:
            fa, fb = 1.0, 0.0
        else:
            fa, fb, fc, fd = self.matrix(0, stop)
            t = self.rows[stop - 1]["thickness"] / self.n_after[stop - 1]
            fa, fb = fa + t * fc, fb + t * fd
        ra, rb, rc, rd = self.matrix(stop, len(self.rows))
        out["entrance_pupil"] = {"position_mm": fb / fa, "diameter_mm": stop_d / abs(fa)}
        out["exit_pupil"] = {"position_mm": -rb / rd, "diameter_mm": stop_d / abs(rd)}
        out["f_number"] = efl / out["entrance_pupil"]["diameter_mm"]
        return out

    # --- real rays ---

    def sag_and_slope(self, i, r2):
        """The sag z(r) at r^2 = r2 and dz/dr divided by r (both finite at r = 0);
        None outside the conic's domain."""
        row = self.rows[i]
        c = 1.0 / row["radius"]
        k = row["k"]
        q = 1.0 - (1.0 + k) * c * c * r2
        if q < 0.0:
            return None
        s = math.sqrt(q)
        z = c * r2 / (1.0 + s)
        slope = c / s
        for n in range(2, 17, 2):
            an = row["a%d" % n]
            if an:
                z += an * r2 ** (n // 2)
                slope += n * an * r2 ** (n // 2 - 1)
        return z, slope

    def intersect(self, i, o, d):
        """Distance along the ray (origin o, unit direction d) to surface i and the unit
        normal there (against the ray); None if it misses."""
        row = self.rows[i]
        zv = self.z[i]
        if row["radius"] == 0.0:
            t = (zv - o[2]) / d[2]
            if not (t > 0.0 and math.isfinite(t)):
                return None
            return t, (0.0, 0.0, -math.copysign(1.0, d[2]))
        radius = row["radius"]
        aspheric = any(row[key] != 0.0 for key in ASPHERE_KEYS)
        # The sphere through the vertex (the base sphere): the root on the vertex's cap.
        cz = zv + radius
        ox, oy, oz = o[0], o[1], o[2] - cz
        b = ox * d[0] + oy * d[1] + oz * d[2]
        cc = ox * ox + oy * oy + oz * oz - radius * radius
        disc = b * b - cc
        t = None
        if disc >= 0.0:
            root = math.sqrt(disc)
            for cand in (-b - root, -b + root):
                if cand > 0.0 and (oz + cand * d[2]) * -radius > 0.0:
                    t = cand
                    break
        if not aspheric:
            if t is None:
                return None
            p = (o[0] + t * d[0], o[1] + t * d[1], o[2] + t * d[2])
            n = (p[0] / abs(radius), p[1] / abs(radius), (p[2] - cz) / abs(radius))
            if n[0] * d[0] + n[1] * d[1] + n[2] * d[2] > 0.0:
                n = (-n[0], -n[1], -n[2])
            return t, n
        # Asphere: Newton steps on F(t) = z(t) - zv - sag(r(t)), from the base sphere's
        # intersection (or the vertex plane's).
        if t is None:
            t = (zv - o[2]) / d[2]
        for _ in range(100):
            x, y = o[0] + t * d[0], o[1] + t * d[1]
            r2 = x * x + y * y
            ss = self.sag_and_slope(i, r2)
            if ss is None:
                return None
            sag, slope = ss
            f = o[2] + t * d[2] - zv - sag
            df = d[2] - slope * (x * d[0] + y * d[1])
            step = f / df
            t -= step
            if abs(step) < 1e-15 * max(1.0, abs(t)):
                break
        else:
            return None
        x, y = o[0] + t * d[0], o[1] + t * d[1]
        ss = self.sag_and_slope(i, x * x + y * y)
        if ss is None or not t > 0.0:
            return None
        slope = ss[1]
        n = (-slope * x, -slope * y, 1.0)
        norm = math.sqrt(n[0] ** 2 + n[1] ** 2 + 1.0)
        n = (n[0] / norm, n[1] / norm, n[2] / norm)
        if n[0] * d[0] + n[1] * d[1] + n[2] * d[2] > 0.0:
            n = (-n[0], -n[1], -n[2])
        return t, n

    def meet(self, i, o, d, clip):
        """(point, normal against the ray) where the ray meets surface i, or None when it
        misses it (or, with `clip`, meets it outside the clear aperture)."""
        hit = self.intersect(i, o, d)
        if hit is None:
            return None
        t, n = hit
        p = (o[0] + t * d[0], o[1] + t * d[1], o[2] + t * d[2])
        half = 0.5 * self.rows[i]["diameter"]
        if clip and p[0] ** 2 + p[1] ** 2 > half * half:
            return None
        return p, n

    def pass_surface(self, i, o, d, clip, backward=False):
        """(origin, direction) after surface i (crossed toward the scene where `backward`),
        or None when blocked."""
        met = self.meet(i, o, d, clip)
        if met is None:
            return None
        p, n = met
        if self.rows[i]["radius"] == 0.0:
            # The stop: an opening, no refraction; the ray goes on from where it was (as in
            # lensray: a stop at a lens vertex would otherwise start the next intersection
            # on that surface).
            return o, d
        eta = self.n_before[i] / self.n_after[i]
        if backward:
            eta = 1.0 / eta
        cos_i = -(n[0] * d[0] + n[1] * d[1] + n[2] * d[2])
        sin2_t = eta * eta * (1.0 - cos_i * cos_i)
        if sin2_t > 1.0:
            return None
        cos_t = math.sqrt(1.0 - sin2_t)
        k = eta * cos_i - cos_t
        return p, (eta * d[0] + k * n[0], eta * d[1] + k * n[1], eta * d[2] + k * n[2])

    def trace(self, o, d, start, end, clip):
        for i in range(start, end):
            out = self.pass_surface(i, o, d, clip)
            if out is None:
                return None
            o, d = out
        return o, d

    def start_z(self):
        return -2.0 * max(r["diameter"] for r in self.rows)

    def chief_ray(self, field_deg, guess_entrance_pupil):
        """(starting height, blocked?) of the real ray at `field_deg` through the stop's
        centre, starting at z = start_z(); None if it cannot reach the stop."""
        w = math.radians(field_deg)
        d = (0.0, math.sin(w), math.cos(w))
        z0 = self.start_z()

        def at_stop(y0):
            out = self.trace((0.0, y0, z0), d, 0, self.stop, clip=False)
            if out is None:
                return None
            hit = self.intersect(self.stop, out[0], out[1])
            if hit is None:
                return None
            return out[0][1] + hit[0] * out[1][1]

        a = (z0 - guess_entrance_pupil) * math.tan(w)
        b = a + 1e-3
        fa, fb = at_stop(a), at_stop(b)
        if fa is None or fb is None:
            return None
        for _ in range(60):
            if abs(fb) < 1e-14 or fb == fa:
                break
            a, fa, b = b, fb, b - fb * (b - a) / (fb - fa)
            fb = at_stop(b)
            if fb is None:
                return None
        return (0.0, b, z0), d

    def blocked(self, ray):
        """Which clear apertures block `ray`: (before the stop?, after the stop?)."""
        o, d = ray
        before = self.trace(o, d, 0, self.stop + 1, clip=True) is None
        whole = self.trace(o, d, 0, len(self.rows), clip=True) is None
        return before, whole and not before

    def height_on_plane(self, ray, z_plane):
        out = self.trace(ray[0], ray[1], 0, len(self.rows), clip=False)
        if out is None:
            return None
        o, d = out
        t = (z_plane - o[2]) / d[2]
        return o[1] + t * d[1]


def chief_rays(lens, first, focus_z, notes):
    """[(field, height)] of the unblocked chief rays on the plane z = focus_z."""
    rows = []
    for field in FIELDS_DEG:
        ray = lens.chief_ray(field, first["entrance_pupil"]["position_mm"])
        if ray is None:
            notes.append("%g deg: no chief ray" % field)
            continue
        before, after = lens.blocked(ray)
        if before:
            notes.append("%g deg: blocked before the stop" % field)
            continue
        if after:
            notes.append("%g deg: blocked after the stop" % field)
            continue
        height = lens.height_on_plane(ray, focus_z)
        if height is None:
            notes.append("%g deg: the chief ray does not reach the film" % field)
            continue
        rows.append((field, height))
    return rows


def dline_data(rows):
    """The figures of `lensray lens --json` (d line)."""
    lens = Lens(rows, LINES_NM["d"])
    out = lens.first_order()
    focus = lens.length + out["bfl_mm"]
    notes = []
    out["chief_ray"] = [
        {"field_deg": f, "image_height_mm": h} for f, h in chief_rays(lens, out, focus, notes)
    ]
    lsa = []
    for fraction in LSA_FRACTIONS:
        h = fraction * 0.5 * out["entrance_pupil"]["diameter_mm"]
        ray = lens.trace((0.0, h, lens.start_z()), (0.0, 0.0, 1.0), 0, len(rows), clip=False)
        if ray is None:
            continue
        o, d = ray
        crossing = o[2] - o[1] * d[2] / d[1]
        lsa.append({"pupil_fraction": fraction, "lsa_mm": crossing - focus})
    out["lsa"] = lsa
    out["tool"] = TOOL
    return out, notes


def colour_data(rows):
    """efl/bfl at F, d, C; axial colour; lateral colour on the d-line focal plane."""
    lenses = {line: Lens(rows, nm) for line, nm in LINES_NM.items()}
    first = {line: lens.first_order() for line, lens in lenses.items()}
    focus = lenses["d"].length + first["d"]["bfl_mm"]
    notes = {}
    heights = {}
    for line in ("F", "C"):
        notes[line] = []
        heights[line] = dict(chief_rays(lenses[line], first[line], focus, notes[line]))
    lateral = [
        {"field_deg": f, "lateral_color_mm": heights["F"][f] - heights["C"][f]}
        for f in FIELDS_DEG
        if f in heights["F"] and f in heights["C"]
    ]
    out = {
        "efl_mm": {line: first[line]["efl_mm"] for line in ("F", "d", "C")},
        "bfl_mm": {line: first[line]["bfl_mm"] for line in ("F", "d", "C")},
        "axial_color_mm": first["F"]["bfl_mm"] - first["C"]["bfl_mm"],
        "lateral_color": lateral,
        "wavelengths_nm": dict(LINES_NM),
        "tool": TOOL,
    }
    return out, notes


def flatten(value, prefix=""):
    """{path: number} of every number in a JSON value (lists of records keyed by their
    first field)."""
    out = {}
    if isinstance(value, dict):
        for k, v in value.items():
            out.update(flatten(v, prefix + "." + k if prefix else k))
    elif isinstance(value, list):
        for n, item in enumerate(value):
            if isinstance(item, dict):
                key = "%s[%s]" % (prefix, list(item.values())[0])
                out.update(flatten({k: v for k, v in list(item.items())[1:]}, key))
            else:
                out.update(flatten(item, "%s[%d]" % (prefix, n)))
    elif isinstance(value, (int, float)) and not isinstance(value, bool):
        out[prefix] = float(value)
    return out


def largest_difference(a, b):
    """(largest |a - b| over the numbers both hold, its key, keys only one holds)."""
    fa, fb = flatten(a), flatten(b)
    worst, where = 0.0, None
    for key in fa.keys() & fb.keys():
        diff = abs(fa[key] - fb[key])
        if diff > worst:
            worst, where = diff, key
    return worst, where, sorted(fa.keys() ^ fb.keys())


def lens_names():
    return sorted(f[:-4] for f in os.listdir(LENS_DIR) if f.endswith(".dat"))


def write_json(path, data):
    with open(path, "w") as f:
        json.dump(data, f, indent=2)
        f.write("\n")


def main(argv):
    write_dline = "--write-dline" in argv
    names = [a for a in argv if not a.startswith("--")] or lens_names()
    for name in names:
        rows = read_lens(os.path.join(LENS_DIR, name + ".dat"))
        colour, notes = colour_data(rows)
        write_json(os.path.join(OUT_DIR, name + ".colour.stdlib.json"), colour)
        print("%-18s efl F/d/C %.6f %.6f %.6f  axial colour %+.6f mm" % (
            name, colour["efl_mm"]["F"], colour["efl_mm"]["d"], colour["efl_mm"]["C"],
            colour["axial_color_mm"]))
        for row in colour["lateral_color"]:
            print("%18s   lateral colour %4.1f deg %+.6f mm" % (
                "", row["field_deg"], row["lateral_color_mm"]))
        for line, n in notes.items():
            for note in n:
                print("%18s   %s line: %s" % ("", line, note))
        dline, dnotes = dline_data(rows)
        path = os.path.join(OUT_DIR, name + ".stdlib.json")
        if os.path.exists(path) and not write_dline:
            with open(path) as f:
                old = json.load(f)
            worst, where, odd = largest_difference(dline, old)
            print("%18s   d line vs %s: largest difference %.2e mm (%s)%s" % (
                "", os.path.basename(path), worst, where,
                "; keys not in both: %s" % odd if odd else ""))
        else:
            write_json(path, dline)
            print("%18s   wrote %s" % ("", os.path.basename(path)))
        for note in dnotes:
            print("%18s   d line: %s" % ("", note))


if __name__ == "__main__":
    main(sys.argv[1:])
