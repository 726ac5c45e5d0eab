#!/usr/bin/env python3
"""Independent model of src/pattern/dither.c (STD maps and serpentine shift, DTAA strata and DTAA*
permutations, Russian-roulette hash, motion-vector alignment) and of the sweep in test/unit/test_dither.c
(test_golden). Enumerates the 9! permutations itself; reads only the blue-noise ranks from
src/pattern/dither_tables.c (test_dither regenerates those with tools/gen/vac.h). Prints the golden values.

    python3 tools/gen/dither_golden.py
"""
import itertools
import os
import re
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from tileorder_golden import M32, combine, hash2, hash3, pcg_hash as pcg  # noqa: E402  (the same hashes)


def score(p):
    s, bad = 0, False
    for r in range(3):
        for c in range(3):
            for q in (3 * r + (c + 1) % 3, 3 * ((r + 1) % 3) + c):
                d = p[3 * r + c] - p[q]
                bad |= abs(d) == 1
                s += d * d
    return s, bad


def maps():
    scored = [(score(p), p) for p in itertools.permutations(range(9))]
    out = []
    for want in (344, 342):
        out += [p for (s, bad), p in scored if not bad and s == want]
    assert len(out) == 288
    return out


here = os.path.dirname(os.path.abspath(__file__))
src = open(os.path.join(here, '..', '..', 'src', 'pattern', 'dither_tables.c')).read()
blue = [int(v) for v in re.findall(r'\d+', src.split('hz_dither_blue64')[1].split('=')[1].split('}')[0])]
assert sorted(blue) == list(range(4096))
MAPS = maps()
PERMS = list(itertools.permutations(range(5)))


def serp(f):
    f %= 18
    x, r = f % 3, f // 3
    if r & 1:
        x = 2 - x
    return x, r % 3


def std_t(x, y, f, m):
    dx, dy = serp(f)
    v = MAPS[m][3 * ((y % 3 + dy) % 3) + (x % 3 + dx) % 3]
    return (((v << 12) + blue[(y % 64) * 64 + x % 64]) << 16) // 36864


def dtaa_t(x, y, f, perm):
    s = (x % 5 + 2 * (y % 5) + 3 * (f % 5)) % 5
    if perm >= 0:
        s = PERMS[perm][s]
    return (((s << 12) + blue[(y % 64) * 64 + x % 64]) << 16) // 20480


def rr_t(a, b, c, f):
    return combine(hash3(a, b, c), f) >> 16


def align(m, al, u):
    step = al << 16
    q = m // step  # Python floors
    rem = m - q * step
    frac = (rem << 16) // step
    if u < frac:
        q += 1
    return (q * step) & M32


def fnv(h, v):
    return ((h ^ (v & M32)) * 16777619) & M32


def main():
    hm = hs = hd = hr = ha = hb = 2166136261
    for o in range(64):
        obj = o * 977
        hm = fnv(hm, (hash3(obj, o & 1, 0x5D1C0DE5) * 288) >> 32)
        hm = fnv(hm, (hash3(obj, o & 1, 0xD7AA5EED) * 120) >> 32)
    for f in range(36):
        for y in range(67):
            for x in range(67):
                hs = fnv(hs, std_t(x, y, f, (x * 7 + y * 13 + f) % 288))
                hd = fnv(hd, dtaa_t(x, y, f, (x + y) % 121 - 1))
                hr = fnv(hr, rr_t(x, y, f * 31, f))
    for i in range(5000):
        mx = (hash2(i, 1) & 0x3FFFFFF) - 0x2000000
        my = (hash2(i, 2) & 0xFFFFFF) - 0x800000
        h = hash2(i, 3)
        al = 3 + 2 * (i & 1)
        ha = fnv(fnv(ha, align(mx, al, h & 0xFFFF)), align(my, al, h >> 16))
    for v in blue:
        hb = fnv(hb, v)
    for name, v in (('OBJECTS', hm), ('STD', hs), ('DTAA', hd), ('RR', hr), ('ALIGN', ha), ('BLUE', hb)):
        print('#define GOLDEN_%s 0x%08xu' % (name, v))


main()
