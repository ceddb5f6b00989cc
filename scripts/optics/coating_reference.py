#!/usr/bin/env python3
"""Thin-film reflectances from an independent package, for lensray-core's tests/coating.rs.

tmm 0.2.0 (Steven Byrnes' transfer-matrix method: `pip install tmm`) computes the reflectance
of a single layer of index n1 and thickness d between media n0 and n2, for s and p light, at
each wavelength and angle of incidence; each case stores their mean (unpolarized light) and
the uncoated interface's. Writes crates/lensray-core/tests/optics_reference/coating.tmm.json.

    target/mitsuba-venv/bin/pip install tmm==0.2.0
    target/mitsuba-venv/bin/python scripts/optics/coating_reference.py
"""
import json
import math
import pathlib

import numpy as np
import tmm

MGF2 = 1.38
DESIGN_NM = 550.0


def reflectance(n_list, d_list, theta, lam):
    r = [tmm.coh_tmm(pol, n_list, d_list, theta, lam)["R"] for pol in ("s", "p")]
    return 0.5 * (r[0] + r[1])


def main():
    cases = []
    thickness = DESIGN_NM / (4.0 * MGF2)
    for n0, n2 in [(1.0, 1.5168), (1.0, 1.7725), (1.5168, 1.0), (1.6204, 1.0), (1.5168, 1.7283)]:
        for degrees in [0.0, 15.0, 35.0, 50.0, 70.0]:
            theta = math.radians(degrees)
            for lam in [400.0, 486.1, 550.0, 656.3, 700.0]:
                coated = reflectance([n0, MGF2, n2], [np.inf, thickness, np.inf], theta, lam)
                bare = reflectance([n0, n2], [np.inf, np.inf], theta, lam)
                cases.append({
                    "n_from": n0,
                    "n_to": n2,
                    "degrees": degrees,
                    "lambda_nm": lam,
                    "coated": float(np.real(coated)),
                    "uncoated": float(np.real(bare)),
                })
    out = pathlib.Path(__file__).resolve().parents[2] / "crates/lensray-core/tests/optics_reference/coating.tmm.json"
    out.write_text(json.dumps({
        "package": f"tmm {tmm.__version__ if hasattr(tmm, '__version__') else '0.2.0'}",
        "layer_index": MGF2,
        "design_nm": DESIGN_NM,
        "cases": cases,
    }, indent=1) + "\n")
    print(f"{out}: {len(cases)} cases")


if __name__ == "__main__":
    main()
