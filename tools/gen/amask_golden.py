#!/usr/bin/env python3
"""Independent model of the adaptive supersampling activity mask (include/hz/adaptive_mask.h, seed 003) for
test_adaptive_mask's golden hash: the same field generator and sweep as test_golden_hash, the rules written
from the header's contract with Python's exact rationals instead of the C code's aligned integers.
Prints the active-subpixel total and the FNV-1a hash the test expects on every ISA."""
import math
import struct
from fractions import Fraction

GW, GH = 48, 40
ONE = 65536
NEIGHBOURS = [[(-1, 0), (-1, -1), (0, -1)], [(0, -1), (1, -1), (1, 0)],
              [(0, 1), (-1, 1), (-1, 0)], [(1, 0), (1, 1), (0, 1)]]
FACTOR = [89129, 66847, 133693]  # round(65536 * 1.36, 1.02, 2.04)
COL, POID, PSN, PSC, PTE, SOID, SSN, SSC, STE = range(9)
NORMAL_COS = 31651  # round(32768 cos 15 deg)


def default_tau():
    return [39322, 3277, 3932, 3932, 39322, 3277, 3932, 3932, 39322]


class LCG:
    def __init__(self, seed):
        self.s = seed

    def __call__(self):
        self.s = (self.s * 1664525 + 1013904223) & 0xffffffff
        return self.s >> 8


def value(bits):
    """Exact value of a binary32 pattern as a Fraction; None for NaN/Inf; negatives as 0."""
    if (bits >> 23) & 0xff == 0xff:
        return None
    if bits >> 31:
        return Fraction(0)
    e, m = (bits >> 23) & 0xff, bits & 0x7fffff
    if e == 0:
        return Fraction(m, 1 << 149)
    return Fraction((1 << 23) | m) * Fraction(2) ** (e - 150)


def contrast_at_least(vals, thr):
    vs = [v for v in (value(b) for b in vals) if v is not None]
    if len(vs) < 2 or thr > ONE:
        return False
    hi, lo = max(vs), min(vs)
    if hi + lo == 0:
        return thr == 0
    # The C code truncates Imin to 31 bits below Imax's leading bit; C differs by < 2^-24, far from any tie here.
    return (hi - lo) / (hi + lo) >= Fraction(thr, ONE)


def normals_differ(a, b, cos_q15):
    la2 = sum(x * x for x in a)
    lb2 = sum(x * x for x in b)
    if la2 == 0 or lb2 == 0:
        return la2 != lb2
    dot = sum(x * y for x, y in zip(a, b))
    c = Fraction(cos_q15, 32768)
    if dot <= 0:
        return c > 0 or dot < 0
    return Fraction(dot * dot, la2 * lb2) < c * c


def focused(focus, p, h):
    """A hit takes part when its object is focused; a reflected hit also when its mirror (the primary hit) is."""
    if not focus:
        return True
    return p['hit'][h]['object'] in focus or (h == 1 and p['hit'][0]['object'] in focus)


def subpixel(tau, focus, p, nbs):
    classes = [(POID, PSN, PSC, PTE), (SOID, SSN, SSC, STE)]
    dis = set()
    for h in range(2):
        oid, sn, sc, te = classes[h]
        a = p['hit'][h]
        a_in = focused(focus, p, h)
        if a['textured'] and a_in:
            dis.add(te)
        for q in nbs:
            b = q['hit'][h]
            if not a_in and not focused(focus, q, h):
                continue
            if a['object'] != b['object']:
                dis.add(oid)
            if a['shadow'] != b['shadow']:
                dis.add(sc)
            if normals_differ(a['n'], b['n'], NORMAL_COS):
                dis.add(sn)
    kept = [tau[k] for k in dis if tau[k] < ONE]
    t = min(kept) if kept else min(tau[COL], ONE)
    for ch in range(3):
        thr = (FACTOR[ch] * t + 32768) >> 16
        if contrast_at_least([p['rgb'][ch]] + [q['rgb'][ch] for q in nbs], thr):
            return True
    return False


def pack(mask, stride, x0, y0, w, h):
    out = []
    side = 1
    while side < 2 * w or side < 2 * h:
        side *= 2
    for code in range(side * side):
        sx = sum(((code >> (2 * b)) & 1) << b for b in range(5))
        sy = sum(((code >> (2 * b + 1)) & 1) << b for b in range(5))
        if sx >= 2 * w or sy >= 2 * h:
            continue
        x, y, q = sx // 2, sy // 2, (sy & 1) * 2 + (sx & 1)
        if mask[(y0 + y) * stride + x0 + x] & (1 << q):
            out.append(((y * w + x) << 2) | q)
    return out


def s8(v):
    return struct.unpack('b', struct.pack('B', v & 0xff))[0]


def main():
    rnd = LCG(2009)
    h = 0x811c9dc5
    total = 0

    def fnv(v):
        nonlocal h
        h = ((h ^ v) * 0x01000193) & 0xffffffff

    for cfg in range(4):
        g = []
        for i in range((GW + 2) * (GH + 2)):
            x, y = i % (GW + 2), i // (GW + 2)
            rgb = []
            for ch in range(3):
                r = rnd()
                e = 123 + (x + 2 * y + ch) // 23
                m = ((x * 97 + y * 31) << 10)
                m = (m + (r & 0x1ffff)) & 0x7fffff
                rgb.append(0x7fc00000 if r % 211 == 0 else 0 if r % 199 == 0 else (e << 23) | m)
            hits = []
            for k in range(2):
                r = rnd()
                hits.append({
                    'object': 0xffff if r % 61 == 0 else ((x + y + 7 * k) // 9) % 5,
                    'shadow': 1 if (x * x + y) % 37 < 5 else 0,
                    'textured': y % 11 == 3,
                    'n': (s8((x * 5) % 255 - 127), s8(((r >> 9) & 7) - 3), 90),
                })
            g.append({'rgb': rgb, 'hit': hits})
        tau = default_tau()
        focus = set()
        if cfg >= 1:
            tau[COL] = 6554 * cfg
            tau[PTE] = 65536
        if cfg == 3:
            focus = {1, 3}
        mask = [0] * (GW * GH)
        stride = GW + 2
        for y in range(GH):
            for x in range(GW):
                p = g[(y + 1) * stride + x + 1]
                m = 0
                for q in range(4):
                    nbs = [g[(y + 1 + dy) * stride + x + 1 + dx] for dx, dy in NEIGHBOURS[q]]
                    if subpixel(tau, focus, p, nbs):
                        m |= 1 << q
                mask[y * GW + x] = m
                total += bin(m).count('1')
        for v in mask:
            fnv(v)
        for ty in range(0, GH, 8):
            for tx in range(0, GW, 16):
                for v in pack(mask, GW, tx, ty, 16, 8):
                    fnv(v)
    print('total %d hash 0x%08x' % (total, h))


if __name__ == '__main__':
    main()
