#!/usr/bin/env python3
"""The tables of lensray's RGB-to-spectrum weighting (crates/lensray-core/src/film/spectral.rs,
which states the definition), written as Rust source to
crates/lensray-interface/src/spectral_table.rs, the one definition of the numbers: the crate
reads them through lensray_core::interface (constants.rs includes the file) and the shaders through
the generated interface.glsl.

    /tmp/optics-venv/bin/python scripts/spectral/tables.py          # writes the file
    /tmp/optics-venv/bin/python scripts/spectral/tables.py --check  # exits 1 if it differs

Needs numpy and colour-science 0.4.7 (the data: the CIE 1931 2 degree standard observer, CIE
illuminant D65, the sRGB basis spectra of Mallett and Yuksel 2019 and sRGB's XYZ-to-RGB matrix).
Everything is computed in float64 and rounded to float32 once, at the end.
"""

import struct
import sys
from pathlib import Path

import colour
import numpy as np

ROOT = Path(__file__).resolve().parent.parent.parent
OUT = ROOT / "crates/lensray-interface/src/spectral_table.rs"

MIN_NM, MAX_NM, STEP_NM = 380, 780, 5
NODES = (MAX_NM - MIN_NM) // STEP_NM + 1
INTERVALS = NODES - 1
# The share of the sampling density that is uniform over the range, so that no interval has
# probability 0 (each has at least UNIFORM_SHARE / INTERVALS).
UNIFORM_SHARE = 0.01
# Gauss-Legendre points per interval for the integral of the Frobenius norm of T'.
NORM_QUADRATURE_POINTS = 16


def f32(x):
    """The float32 nearest to x, as a Python float."""
    return struct.unpack("<f", struct.pack("<f", x))[0]


def data():
    """Wavelengths, the matching functions (81 x 3), D65 (81), the basis (81 x 3), M (3 x 3)."""
    lam = np.arange(MIN_NM, MAX_NM + 1, STEP_NM, dtype=np.float64)
    cmfs = colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"]
    d65 = colour.SDS_ILLUMINANTS["D65"]
    basis = colour.recovery.MSDS_BASIS_FUNCTIONS_sRGB_MALLETT2019
    # Every node is a wavelength of each data set (1 nm or 5 nm steps): values, not
    # interpolations.
    for ds in (cmfs, d65, basis):
        assert set(lam) <= set(ds.wavelengths), ds.name
    xyz = np.array([cmfs[w] for w in lam], dtype=np.float64)
    e = np.array([d65[w] for w in lam], dtype=np.float64)
    b = np.array([basis[w] for w in lam], dtype=np.float64)
    m = np.array(colour.RGB_COLOURSPACES["sRGB"].matrix_XYZ_to_RGB, dtype=np.float64)
    return lam, xyz, e, b, m


def trapezoid(values):
    """The integral over [MIN_NM, MAX_NM] of the piecewise-linear interpolation of node values
    (axis 0)."""
    w = np.full(NODES, float(STEP_NM))
    w[0] = w[-1] = STEP_NM / 2
    return np.tensordot(w, values, axes=(0, 0))


def weights():
    """T' at the nodes (81 x 3 x 3), R, N and M."""
    lam, xyz, e, b, m = data()
    assert np.allclose(b.sum(axis=1), 1.0, atol=1e-12), "the basis spectra sum to 1"
    n = trapezoid(xyz[:, 1] * e)
    t = np.einsum("ij,nj,nk->nik", m, xyz, e[:, None] * b) / n
    r = trapezoid(t)
    t_prime = np.einsum("ij,njk->nik", np.linalg.inv(r), t)
    return t_prime, r, n, m


def interval_masses(t_prime):
    """The integral over each interval of the Frobenius norm of the interpolated T'."""
    x, w = np.polynomial.legendre.leggauss(NORM_QUADRATURE_POINTS)
    s = (x + 1) / 2  # position in the interval, [0, 1]
    masses = np.empty(INTERVALS)
    for i in range(INTERVALS):
        inner = (1 - s)[:, None, None] * t_prime[i] + s[:, None, None] * t_prime[i + 1]
        norms = np.sqrt((inner**2).sum(axis=(1, 2)))
        masses[i] = STEP_NM / 2 * (w * norms).sum()
    return masses


def density(t_prime):
    """The float32 cumulative table (81), and per interval 1 / P (float32) and 1 / p in 1/nm
    (float32), both from the float32 table's own interval probabilities, so that the density
    the search samples and the one the weights divide by are the same."""
    masses = interval_masses(t_prime)
    p = (1 - UNIFORM_SHARE) * masses / masses.sum() + UNIFORM_SHARE / INTERVALS
    cdf64 = np.concatenate([[0.0], np.cumsum(p)])
    cdf = [f32(c) for c in cdf64]
    cdf[0], cdf[-1] = 0.0, 1.0
    prob = [cdf[i + 1] - cdf[i] for i in range(INTERVALS)]  # exact in float64
    assert all(q > 0 for q in prob), "the cumulative table rises strictly"
    inv_prob = [f32(1 / q) for q in prob]
    inv_density = [f32(STEP_NM / q) for q in prob]
    return cdf, prob, inv_prob, inv_density


def literal(x):
    """A Rust f32 literal that reads back as the float32 x (repr of float32 x: round trip)."""
    # The shortest digits that read back as x, positional or with an exponent, whichever is
    # shorter: "0.2", "1.7927547e-06".
    v = np.float32(x)
    texts = [
        np.format_float_positional(v, unique=True, trim="0"),
        np.format_float_scientific(v, unique=True, trim="0"),
    ]
    text = min(texts, key=len)
    assert f32(float(text)) == x, (x, text)
    return text


def row_text(row):
    return "  ".join(f"{v:+.10f}" for v in row)


def rust_array(name, values, doc, per_line=6):
    lines = [f"/// {d}" for d in doc]
    lines.append(f"pub(super) const {name}: [f32; {len(values)}] = [")
    for k in range(0, len(values), per_line):
        lines.append("    " + ", ".join(literal(v) for v in values[k : k + per_line]) + ",")
    lines.append("];")
    return "\n".join(lines)


def source():
    t_prime, r, n, m = weights()
    cdf, prob, inv_prob, inv_density = density(t_prime)
    flat = []
    for node in t_prime:
        flat.extend(f32(v) for v in node.T.reshape(-1))  # column-major, as glam's Mat3
    dev = np.abs(r - np.eye(3)).max()
    header = [
        "// Generated by scripts/spectral/tables.py (colour-science "
        f"{colour.__version__}); do not edit. The definition is",
        "// crates/lensray-core/src/film/spectral.rs; constants.rs includes this file, so it holds",
        "// only items (no inner attributes, no crate paths).",
        "//",
        f"// N = {float(n):.10g} (the trapezoid of ybar * D65).",
        "// M (linear sRGB from XYZ), rows:",
        *(f"//   {row_text(row)}" for row in m),
        "// R (the integral of T, before T' = R^-1 T), rows:",
        *(f"//   {row_text(row)}" for row in r),
        f"// Its largest difference from I: {dev:.3e}.",
        f"// Sampling density: {1 - UNIFORM_SHARE:g} proportional to the integral of |T'|_F over "
        f"each interval, {UNIFORM_SHARE:g} uniform;",
        f"// the least interval probability is {min(prob):.4e}.",
        "",
    ]
    consts = [
        "/// The first and last node, and the spacing of the nodes, in nm.",
        f"pub(super) const MIN_NM: f32 = {MIN_NM}.0;",
        f"pub(super) const MAX_NM: f32 = {MAX_NM}.0;",
        f"pub(super) const STEP_NM: f32 = {STEP_NM}.0;",
        "/// 1 / STEP_NM, rounded to f32 (the weights' interval index and position multiply by it).",
        f"pub(super) const INV_STEP_NM: f32 = {literal(f32(1 / STEP_NM))};",
        f"pub(super) const NODES: u32 = {NODES};",
        "",
        rust_array(
            "WEIGHTS",
            flat,
            ["T' at each node: 9 per node, the 3x3 matrix column by column (glam's Mat3)."],
            per_line=3,
        ),
        "",
        rust_array(
            "CDF",
            cdf,
            ["The cumulative probability at each node: 0 at the first, 1 at the last."],
        ),
        "",
        rust_array(
            "INV_PROBABILITY",
            inv_prob,
            ["1 / (CDF[i + 1] - CDF[i]) per interval."],
        ),
        "",
        rust_array(
            "INV_DENSITY",
            inv_density,
            ["STEP_NM / (CDF[i + 1] - CDF[i]) per interval: 1 / p in nm."],
        ),
        "",
    ]
    return "\n".join(header + consts)


def main():
    text = source()
    if "--check" in sys.argv[1:]:
        if OUT.read_text() != text:
            print(f"{OUT} differs from what {Path(__file__).name} generates")
            sys.exit(1)
        print(f"{OUT} is up to date")
        return
    OUT.write_text(text)
    print(f"wrote {OUT}")


if __name__ == "__main__":
    main()
