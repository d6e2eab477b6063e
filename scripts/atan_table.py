#!/usr/bin/env python3
"""Regenerates ATAN_TABLE in src/math/atan.rs and checks its fixed-point error.

atan t on [k/64, (k+1)/64], k = 8..63, as a degree-3 minimax polynomial in
d = t - k/64 (Remez exchange, mpmath at 100 bits), coefficients rounded to
Q0.32. Rows are [c0, c1, -c2, c3] (c3 as a two's-complement u32). The check
runs the chip's integer evaluation (atan_mid, bit for bit) on 2e5 random t
and every interval edge and prints the worst error in units of 2^-31.

usage: python3 scripts/atan_table.py   (needs mpmath)
"""
import math
import random

import mpmath as mp

mp.mp.prec = 100
W = mp.mpf(1) / 64
M = 0xFFFFFFFF


def fit(k, n=3, grid=400):
    a = mp.mpf(k) / 64
    f = lambda d: mp.atan(a + d)
    xs = [W / 2 - W / 2 * mp.cos(mp.pi * i / (n + 1)) for i in range(n + 2)]
    for _ in range(8):
        A = mp.matrix(n + 2, n + 2)
        b = mp.matrix(n + 2, 1)
        for i, x in enumerate(xs):
            for j in range(n + 1):
                A[i, j] = x**j
            A[i, n + 1] = (-1) ** i
            b[i] = f(x)
        sol = mp.lu_solve(A, b)
        c = [sol[j] for j in range(n + 1)]
        g = [W * i / grid for i in range(grid + 1)]
        e = [f(x) - sum(c[j] * x**j for j in range(n + 1)) for x in g]
        ext = [0] + [i for i in range(1, grid) if (e[i] - e[i - 1]) * (e[i + 1] - e[i]) <= 0] + [grid]
        if len(ext) == n + 2:
            xs = [g[i] for i in ext]
    return c, max(abs(v) for v in e)


def mul_hi_approx(a, b):
    a1, a0, b1, b0 = a >> 16, a & 0xFFFF, b >> 16, b & 0xFFFF
    lh, hl = a0 * b1, a1 * b0
    return (a1 * b1 + (lh >> 16) + (hl >> 16) + (((lh & 0xFFFF) + (hl & 0xFFFF)) >> 16)) & M


def atan_mid(rows, t31):
    k = max(8, min(63, t31 >> 25))
    d = ((t31 - (k << 25)) << 1) & M
    c0, c1, m2, c3 = rows[k - 8]
    c3s = c3 - (1 << 32) if c3 >> 31 else c3
    p3 = ((abs(c3s) >> 16) * (d >> 11)) >> 5
    n2 = m2 + p3 if c3s < 0 else m2 - p3
    v1 = c1 - mul_hi_approx(n2, d)
    v0 = c0 + mul_hi_approx(v1, d)
    assert 0 < n2 and 0 < v1 and v0 <= M
    return (v0 >> 1) + (v0 & 1)


def main():
    rows, worst_fit = [], 0
    for k in range(8, 64):
        c, e = fit(k)
        worst_fit = max(worst_fit, e)
        q = [int(mp.nint(ci * 2**32)) for ci in c]
        rows.append([q[0], q[1], -q[2], q[3] & M])
    print("static ATAN_TABLE: [[u32; 4]; 56] = [")
    for r in rows:
        print("    [" + ", ".join("0x%04X_%04X" % (v >> 16, v & 0xFFFF) for v in r) + "],")
    print("];")
    random.seed(1)
    ts = [random.randrange(1 << 28, (1 << 31) + 1) for _ in range(200_000)]
    ts += [(k << 25) + o for k in range(8, 65) for o in (-1, 0, 1) if (1 << 28) <= (k << 25) + o <= 1 << 31]
    err = max(abs(atan_mid(rows, t) - math.atan(t / 2**31) * 2**31) for t in ts)
    print("// fit error %.3g; fixed-point error %.3f units of 2^-31" % (worst_fit, err))


main()
