#!/usr/bin/env python3
"""Independent model of src/pattern/tileorder.c (integer CORDIC angle, fractional length, the six ĝ rules)
and of the sweep in test/unit/test_tileorder.c (test_golden_hash). Prints the golden values that test
asserts, so a change in either implementation, or a difference between ISAs, shows up as a mismatch.

    python3 tools/gen/tileorder_golden.py
"""
import math

M32 = 0xFFFFFFFF
M64 = 0xFFFFFFFFFFFFFFFF


def fmix32(x):
    x ^= x >> 16
    x = (x * 0x85EBCA6B) & M32
    x ^= x >> 13
    x = (x * 0xC2B2AE35) & M32
    x ^= x >> 16
    return x


def pcg_hash(v):
    state = (v * 747796405 + 2891336453) & M32
    word = (((state >> ((state >> 28) + 4)) ^ state) * 277803737) & M32
    return (word >> 22) ^ word


def combine(seed, v):
    return fmix32(seed ^ ((pcg_hash(v) + 0x9E3779B9 + ((seed << 6) & M32) + (seed >> 2)) & M32))


def hash2(a, b):
    return combine(pcg_hash(a), b)


def hash3(a, b, c):
    return combine(combine(pcg_hash(a), b), c)


class Pcg32:
    def __init__(self, seed, stream):
        self.state = 0
        self.inc = ((stream << 1) | 1) & M64
        self.next()
        self.state = (self.state + seed) & M64
        self.next()

    def next(self):
        old = self.state
        self.state = (old * 6364136223846793005 + self.inc) & M64
        xs = (((old >> 18) ^ old) >> 27) & M32
        rot = old >> 59
        return ((xs >> rot) | (xs << ((-rot) & 31))) & M32


def s32(u):
    u &= M32
    return u - (1 << 32) if u & 0x80000000 else u


RIGHT = 1 << 30
DIAG = 1 << 29
GAMMA = (1 << 30) // 20  # π/40 in 2^-30 quarter turns, rounded down
# The micro-rotation table is recomputed from libm here, not copied from the C source.
ATAN = [int(math.floor(math.atan(2.0 ** -i) / (math.pi / 2) * 2 ** 38 + 0.5)) for i in range(34)]


def angle(mx, my):
    ax, ay = abs(mx), abs(my)
    if ay == 0:
        return 0
    if ax == 0:
        return RIGHT
    if ax == ay:
        return DIAG
    big = max(ax, ay)
    shift = 60 - (big.bit_length() - 1)
    x, y, z = ax << shift, ay << shift, 0
    for i in range(34):
        dx, dy = y >> i, x >> i  # Python's >> floors, like floor_shift
        if y >= 0:
            x, y, z = x + dx, y - dy, z + ATAN[i]
        else:
            x, y, z = x - dx, y + dy, z - ATAN[i]
    z = min(max(z, 0), RIGHT << 8)
    return (z + 128) >> 8


def length_frac(mx, my):
    return math.isqrt(mx * mx + my * my) & 0xFFFF


HG, BT = 1, 2


def horiz(lf):
    return HG if 0x4000 < lf < 0xC000 else BT


def vert(lf):
    return BT if 0x4000 < lf < 0xC000 else HG


def shear(lf, a, up):
    h = a >> 15
    u = ((lf - h) if up else (lf + h)) & 0xFFFF
    return HG if 0x4000 < u < 0xC000 else BT


def ghat(mx, my, rnd, rule):
    if rule == 4:
        return HG
    if rule == 5:
        return BT
    lf = length_frac(mx, my)
    if my == 0:
        return horiz(lf)
    if mx == 0:
        return vert(lf)
    if rule == 1:
        return horiz(lf) if abs(mx) >= abs(my) else vert(lf)
    a = angle(mx, my)
    if rule == 2:
        return shear(lf, a, True)
    if rule == 3:
        return shear(lf, a, False)
    if a <= DIAG - GAMMA:
        return shear(lf, a, True)
    if a >= DIAG + GAMMA:
        return shear(lf, a, False)
    return HG if rnd >> 31 else BT


def motions():
    out = []
    for j in range(-40, 41):
        for i in range(-40, 41):
            out.append((i * 3277, j * 3277))
    r = Pcg32(7, 11)
    for _ in range(4096):
        a = s32(r.next()) >> (r.next() & 31)
        b = s32(r.next()) >> (r.next() & 31)
        out.append((a, b))
    ext = [-(1 << 31), (1 << 31) - 1, -1, 0, 1, 1 << 14, 3 << 14]
    for a in ext:
        for b in ext:
            out.append((a, b))
    return out


def mix(h, v):
    return ((h ^ (v & M32)) * 0x01000193) & M32


def main():
    h_angle = h_frac = h_rule = 0x811C9DC5
    for k, (mx, my) in enumerate(motions()):
        h_angle = mix(h_angle, angle(mx, my))
        h_frac = mix(h_frac, length_frac(mx, my))
        rnd = hash3(k, 0, hash2(3, 5))
        for rule in range(6):
            h_rule = mix(h_rule, ghat(mx, my, rnd, rule))
    print("cases %d" % len(motions()))
    print("angle 0x%08x" % h_angle)
    print("frac  0x%08x" % h_frac)
    print("ghat  0x%08x" % h_rule)


if __name__ == "__main__":
    main()
