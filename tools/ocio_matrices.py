#!/usr/bin/env python3
"""Derives the MatrixTransforms of presets/ocio/config.ocio from published chromaticities.

Every colour space of the config is defined relative to the reference "CIE XYZ D65": the CIE 1931
tristimulus values that firmament computes from spectra, with D65 as the adopted white.  A space
with RGB primaries gets M = RGB -> XYZ built the usual way (columns = primaries' XYZ scaled so that
RGB = 1 gives the white with Y = 1).  When the space's white is not D65 (ACES, white ~D60) the
result is Bradford-adapted from that white to D65, so that a D65 stimulus stays neutral.

Chromaticities (CIE 1931 x, y):
  Rec.709 / sRGB  ITU-R BT.709-6, IEC 61966-2-1: R 0.64 0.33, G 0.30 0.60, B 0.15 0.06, D65
  Rec.2020        ITU-R BT.2020-2: R 0.708 0.292, G 0.170 0.797, B 0.131 0.046, D65
  D65             x 0.3127, y 0.3290 (the 4-digit value used by BT.709 / sRGB)
  AP0             SMPTE ST 2065-1: R 0.7347 0.2653, G 0.0 1.0, B 0.0001 -0.0770
  AP1             Academy S-2014-004 (ACEScg): R 0.713 0.293, G 0.165 0.830, B 0.128 0.044
  ACES white      x 0.32168, y 0.33767 (~D60)
Bradford cone response matrix: Lam (1985), as published by Hunt / Lindbloom.

Run: python3 tools/ocio_matrices.py   (prints the 4x4 matrices, row-major, as the config writes them)
"""


def mat_mul(a, b):
    return [[sum(a[i][k] * b[k][j] for k in range(3)) for j in range(3)] for i in range(3)]


def mat_vec(a, v):
    return [sum(a[i][k] * v[k] for k in range(3)) for i in range(3)]


def mat_inv(m):
    det = (m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
           m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]))
    inv = [[0.0] * 3 for _ in range(3)]
    for i in range(3):
        for j in range(3):
            r0, r1, c0, c1 = (j + 1) % 3, (j + 2) % 3, (i + 1) % 3, (i + 2) % 3
            inv[i][j] = (m[r0][c0] * m[r1][c1] - m[r0][c1] * m[r1][c0]) / det
    return inv


def xy_to_xyz(x, y):
    return [x / y, 1.0, (1.0 - x - y) / y]


def rgb_to_xyz(primaries, white):
    """primaries: ((xr, yr), (xg, yg), (xb, yb)); white: (xw, yw)."""
    cols = [xy_to_xyz(*p) for p in primaries]
    p = [[cols[j][i] for j in range(3)] for i in range(3)]
    s = mat_vec(mat_inv(p), xy_to_xyz(*white))
    return [[p[i][j] * s[j] for j in range(3)] for i in range(3)]


BRADFORD = [[0.8951, 0.2664, -0.1614], [-0.7502, 1.7135, 0.0367], [0.0389, -0.0685, 1.0296]]


def bradford(src_white, dst_white):
    """XYZ under src_white -> corresponding XYZ under dst_white (von Kries in Bradford cone space)."""
    s = mat_vec(BRADFORD, xy_to_xyz(*src_white))
    d = mat_vec(BRADFORD, xy_to_xyz(*dst_white))
    scale = [[d[i] / s[i] if i == j else 0.0 for j in range(3)] for i in range(3)]
    return mat_mul(mat_inv(BRADFORD), mat_mul(scale, BRADFORD))


D65 = (0.3127, 0.3290)
ACES_WHITE = (0.32168, 0.33767)
REC709 = ((0.64, 0.33), (0.30, 0.60), (0.15, 0.06))
REC2020 = ((0.708, 0.292), (0.170, 0.797), (0.131, 0.046))
AP0 = ((0.7347, 0.2653), (0.0, 1.0), (0.0001, -0.0770))
AP1 = ((0.713, 0.293), (0.165, 0.830), (0.128, 0.044))


def space_to_xyz_d65(primaries, white):
    m = rgb_to_xyz(primaries, white)
    return m if white == D65 else mat_mul(bradford(white, D65), m)


def matrix44(m):
    rows = [list(r) + [0.0] for r in m] + [[0.0, 0.0, 0.0, 1.0]]
    # entries that are 0 in exact arithmetic come out of the inversion as ~1e-17
    return "[" + ", ".join("%.10g" % (0.0 if abs(v) < 1e-12 else v) for r in rows for v in r) + "]"


def main():
    for name, prim, white in (("Linear Rec.709", REC709, D65), ("Linear Rec.2020", REC2020, D65), ("ACEScg", AP1, ACES_WHITE),
                              ("ACES2065-1", AP0, ACES_WHITE)):
        print("%s -> CIE XYZ D65 (to_scene_reference):\n  matrix: %s" % (name, matrix44(space_to_xyz_d65(prim, white))))


if __name__ == "__main__":
    main()
