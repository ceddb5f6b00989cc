#!/usr/bin/env python3
"""The glasses of lensray's built-in lenses against the glass makers' catalogues.

Needs: pip install rayoptics==0.9.8 optiland==0.6.3 opticalglass==1.1.1
(only opticalglass is used here).

    python scripts/optics/glasses.py [--nearest N_D ...]

Prints, as a Markdown table for crates/lensray/tests/lens_reference/README.md, every glass of
every built-in lens (assets/lenses/*.dat): the glass it stands for (GLASSES below, as the
files' comments say), the file's n_d and V_d beside the catalogue's, n at the F, d and C lines
from lensray's two-term Cauchy model (issue 31, through the file's n_d and V_d) beside the
catalogue's own dispersion formula at the same wavelengths (486.13, 587.56, 656.27 nm), and
the model's own error: Cauchy through the catalogue's n_d and V_d minus the catalogue's
formula, at F and C.

`--nearest 1.603 1.717 ...` lists the glasses of Schott's current catalogue nearest each n_d
(how the glasses of double-gauss-50 and wide-22 were chosen: the nearest n_d; among equal
n_d, an N- glass before its lead-glass twin and the plain grade before HT / HTultra).
"""

import os
import sys

import opticalglass.glassfactory as gf

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import colour_reference as cr  # noqa: E402  (the .dat reader and the Cauchy model)

LINES = ("F", "d", "C")

# The glass each glass row stands for, in row order: (catalogue, name).
GLASSES = {
    "biconvex-50": [("Schott", "N-BK7")],
    "cooke-triplet-50": [("Schott", "N-SK16"), ("Schott", "F2"), ("Schott", "N-SK16")],
    "double-gauss-50": [
        ("Schott", "N-BAF10"),
        ("Schott", "N-BAF10"),
        ("Schott", "N-SF15"),
        ("Schott", "F5"),
        ("Schott", "N-SSK5"),
        ("Hoya", "LAF3"),
    ],
    "wide-22": [
        ("Schott", "N-BAK2"),
        ("Schott", "N-LAF34"),
        ("Schott", "N-SSK8"),
        ("Schott", "N-SSK8"),
        ("Schott", "N-LAK8"),
        ("Schott", "N-SF6"),
        ("Schott", "N-SSK8"),
    ],
    "achromat-50": [("Schott", "N-BAK1"), ("Schott", "SF2")],
    "aspheric-31": [
        ("Hikari", "J-LAK14"),
        ("Ohara", "S-TIM28"),
        ("Schott", "SF11"),
        ("Hoya", "TAF3"),
        ("Hoya", "TAFD30"),
    ],
}


def catalogue_nd_vd(catalogue, name):
    """The catalogue's tabulated n_d and V_d."""
    data = gf.get_glass_catalog(catalogue).glass_data(name)
    nd = vd = None
    for key, value in data.items():
        group, item = key
        if item == "d" and isinstance(group, str) and group.startswith("refractive ind"):
            nd = float(value)
        if item == "nd" and nd is None:
            nd = float(value)
        if item == "νd":  # Ohara: V_d to 2 decimals (its 'vd' column is rounded to 1)
            vd = float(value)
        if item == "vd" and group == "abbe number" and vd is None:
            vd = float(value)
    return nd, vd


def catalogue_index(catalogue, name, wavelength_nm):
    """The catalogue's dispersion formula at `wavelength_nm`."""
    return float(gf.create_glass(name, catalogue).rindex(wavelength_nm))


def schott_glasses():
    cat = gf.get_glass_catalog("Schott")
    out = []
    for name in cat.get_glass_names():
        nd, vd = catalogue_nd_vd("Schott", name)
        out.append((name, nd, vd))
    return out


def nearest(nd, glasses, count=5):
    def key(g):
        name = g[0]
        return (
            round(abs(g[1] - nd), 6),
            0 if name.startswith("N-") else 1,
            1 if "HT" in name else 0,
            name,
        )

    return sorted(glasses, key=key)[:count]


FORMULA = {"Schott": "Sellmeier", "Ohara": "Sellmeier", "Hoya": "power series",
           "Hikari": "power series"}


def table():
    """One row per glass per lens: (lens, rows, catalogue, name, file n_d, file V_d,
    catalogue n_d, catalogue V_d, Cauchy n at F/d/C through the file's n_d and V_d,
    the catalogue's formula at F/d/C, Cauchy through the catalogue's n_d and V_d)."""
    out = []
    for lens, glasses in GLASSES.items():
        path = os.path.join(cr.LENS_DIR, lens + ".dat")
        if not os.path.exists(path):
            continue
        rows = cr.read_lens(path)
        glass_rows = [(k + 1, r) for k, r in enumerate(rows) if r["nd"] != 1.0]
        if len(glass_rows) != len(glasses):
            raise SystemExit("%s: %d glass rows, %d glasses listed" % (
                lens, len(glass_rows), len(glasses)))
        seen = {}
        for (number, row), (catalogue, name) in zip(glass_rows, glasses):
            key = (catalogue, name, row["nd"], row["vd"])
            if key in seen:
                seen[key][1].append(number)
                continue
            nd, vd = catalogue_nd_vd(catalogue, name)
            entry = [lens, [number], catalogue, name, row["nd"], row["vd"], nd, vd,
                     {line: cr.cauchy(row["nd"], row["vd"], cr.LINES_NM[line]) for line in LINES},
                     {line: catalogue_index(catalogue, name, cr.LINES_NM[line]) for line in LINES},
                     {line: cr.cauchy(nd, vd, cr.LINES_NM[line]) for line in LINES}]
            seen[key] = entry
            out.append(entry)
    return out


def main(argv):
    if argv and argv[0] == "--nearest":
        glasses = schott_glasses()
        for value in argv[1:]:
            nd = float(value)
            print("%s: %s" % (value, ", ".join(
                "%s %.5f/%.2f" % g for g in nearest(nd, glasses))))
        return
    rows = table()
    worst_model = worst_file = 0.0
    for lens, numbers, catalogue, name, fnd, fvd, nd, vd, model, cat, own in rows:
        if abs(fvd - vd) > 0.005:
            print("%s rows %s: V_d %.2f in the file, %.2f in the catalogue" % (
                lens, numbers, fvd, vd))
        worst_model = max(worst_model, *(abs(own[line] - cat[line]) for line in LINES))
        worst_file = max(worst_file, *(abs(model[line] - cat[line]) for line in LINES))
    print("| lens | rows | glass (maker; formula) | file n_d / V_d | catalogue n_d / V_d "
          "| n_F Cauchy / catalogue | n_d Cauchy / catalogue | n_C Cauchy / catalogue "
          "| model error F / C |")
    print("|---|---|---|---|---|---|---|---|---|")
    for lens, numbers, catalogue, name, fnd, fvd, nd, vd, model, cat, own in rows:
        print("| %s | %s | %s (%s; %s) | %.5f / %.2f | %.5f / %.2f | %s | %s | %s | %+.1e / %+.1e |"
              % (lens, ", ".join(map(str, numbers)), name, catalogue, FORMULA[catalogue],
                 fnd, fvd, nd, vd,
                 *("%.5f / %.5f" % (model[line], cat[line]) for line in LINES),
                 own["F"] - cat["F"], own["C"] - cat["C"]))
    print()
    print("Largest |n_Cauchy - n_catalogue| at F, d, C: %.1e through the catalogue's n_d and "
          "V_d (the two-term model's error), %.1e through the files' own n_d and V_d."
          % (worst_model, worst_file))


if __name__ == "__main__":
    main(sys.argv[1:])
