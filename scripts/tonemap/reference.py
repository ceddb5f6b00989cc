#!/usr/bin/env python3
"""Reference values of the tone maps, for lensray-core's tests (film/tonemap tests).

Each function is a statement-by-statement transcription of the published reference code,
evaluated in double precision (Python floats), with no other code of lensray's:

- Khronos PBR Neutral: the Khronos specification "PBR Neutral Tone Mapping" and its reference
  code, https://github.com/KhronosGroup/ToneMapping, PBR_Neutral/pbrNeutral.glsl
  (PBRNeutralToneMapping).
- AgX: three.js, src/renderers/shaders/ShaderChunk/tonemapping_pars_fragment.glsl.js
  (AgXToneMapping with toneMappingExposure = 1, its matrices with all their digits), after
  Filament's port (google/filament#7236) of Blender's AgX.

Run: python3 scripts/tonemap/reference.py  (prints Rust arrays to paste into the tests).
"""
import math
import struct


def neutral(color):
    start_compression = 0.8 - 0.04
    desaturation = 0.15
    x = min(color)
    offset = x - 6.25 * x * x if x < 0.08 else 0.04
    color = [c - offset for c in color]
    peak = max(color)
    if peak < start_compression:
        return color
    d = 1.0 - start_compression
    new_peak = 1.0 - d * d / (peak + d - start_compression)
    color = [c * new_peak / peak for c in color]
    g = 1.0 - 1.0 / (desaturation * (peak - new_peak) + 1.0)
    return [c * (1.0 - g) + new_peak * g for c in color]


def mat3(*cols):
    """GLSL's mat3(vec3, vec3, vec3): the arguments are columns."""
    return cols


def mul(m, v):
    return [sum(m[c][r] * v[c] for c in range(3)) for r in range(3)]


LINEAR_REC2020_TO_LINEAR_SRGB = mat3(
    (1.6605, -0.1246, -0.0182), (-0.5876, 1.1329, -0.1006), (-0.0728, -0.0083, 1.1187))
LINEAR_SRGB_TO_LINEAR_REC2020 = mat3(
    (0.6274, 0.0691, 0.0164), (0.3293, 0.9195, 0.0880), (0.0433, 0.0113, 0.8956))
AGX_INSET = mat3(
    (0.856627153315983, 0.137318972929847, 0.11189821299995),
    (0.0951212405381588, 0.761241990602591, 0.0767994186031903),
    (0.0482516061458583, 0.101439036467562, 0.811302368396859))
AGX_OUTSET = mat3(
    (1.1271005818144368, -0.1413297634984383, -0.14132976349843826),
    (-0.11060664309660323, 1.157823702216272, -0.11060664309660294),
    (-0.016493938717834573, -0.016493938717834257, 1.2519364065950405))
AGX_MIN_EV = -12.47393
AGX_MAX_EV = 4.026069


def contrast_approx(x):
    x2 = x * x
    x4 = x2 * x2
    return (15.5 * x4 * x2 - 40.14 * x4 * x + 31.96 * x4 - 6.868 * x2 * x + 0.4298 * x2
            + 0.1191 * x - 0.00232)


def agx(color):
    color = mul(LINEAR_SRGB_TO_LINEAR_REC2020, color)
    color = mul(AGX_INSET, color)
    color = [max(c, 1e-10) for c in color]
    color = [math.log2(c) for c in color]
    color = [(c - AGX_MIN_EV) / (AGX_MAX_EV - AGX_MIN_EV) for c in color]
    color = [min(max(c, 0.0), 1.0) for c in color]
    color = [contrast_approx(c) for c in color]
    color = mul(AGX_OUTSET, color)
    color = [max(0.0, c) ** 2.2 for c in color]
    color = mul(LINEAR_REC2020_TO_LINEAR_SRGB, color)
    return [min(max(c, 0.0), 1.0) for c in color]


INPUTS = [
    (0.0, 0.0, 0.0), (0.01, 0.01, 0.01), (0.05, 0.05, 0.05), (0.18, 0.18, 0.18),
    (0.5, 0.5, 0.5), (0.76, 0.76, 0.76), (1.0, 1.0, 1.0), (2.0, 2.0, 2.0), (16.0, 16.0, 16.0),
    (100.0, 100.0, 100.0), (1.0, 0.5, 0.25), (0.8, 0.1, 0.05), (0.02, 0.3, 0.6),
    (5.0, 2.0, 0.5), (50.0, 10.0, 1.0),
]


def lit(x):
    """The shortest Rust literal of x rounded to f32 (what the tests compare in)."""
    v = struct.unpack('f', struct.pack('f', x))[0]
    for digits in range(1, 10):
        t = '%.*g' % (digits, v)
        if struct.unpack('f', struct.pack('f', float(t)))[0] == v:
            break
    return t if ('.' in t or 'e' in t) else t + '.0'


def rust(name, f):
    print(f"const {name}: [([f32; 3], [f32; 3]); {len(INPUTS)}] = [")
    for i in INPUTS:
        o = f(list(i))
        print(f"    ([{', '.join(repr(float(x)) for x in i)}], [{', '.join(lit(x) for x in o)}]),")
    print("];")


if __name__ == "__main__":
    rust("NEUTRAL", neutral)
    rust("AGX", agx)
