#!/usr/bin/env python3
"""Independent model of src/pattern/timeseq.c (stratified shutter times, src/pattern/timeseq.h's definition) and of the
sweep in test/unit/test_timeseq.c (test_golden_sweep). Prints the golden value that test asserts, so a change
of the sequence, or a difference between ISAs, shows up as a mismatch.

    python3 tools/gen/timeseq_golden.py
"""

import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from tileorder_golden import M32, hash2, hash3  # noqa: E402 (hz/hash.h's model, shared)


def stratum(pixel, index, count, seed):
    if count <= 1:
        return 0
    index %= count
    bits = 0
    while (1 << bits) < count:
        bits += 1
    mask = (1 << bits) - 1
    key = hash2(pixel, seed ^ 0x7F4A7C15)
    i = index
    while True:
        i = (i * 0x2C1B3C6D + key) & mask
        if bits > 3:
            i ^= i >> 3
        i = (i ^ (key >> 16)) & mask
        if i < count:
            return i


def ceil_div(a, b):
    return -(-a // b)


def time_u32(pixel, index, count, seed):
    count = max(count, 1)
    index %= count
    s = stratum(pixel, index, count, seed)
    lo, hi = ceil_div(s << 32, count), ceil_div((s + 1) << 32, count)
    j = hash3(pixel, index, seed ^ 0x3C6EF372)
    return lo + ((j * (hi - lo)) >> 32)


def sweep():
    """test_golden_sweep: h = h * 31 + f over pixels 0..299, counts 1, 2, 4, 9, 16, 64, 256, 1000, seeds 0, 7."""
    h = 0
    for seed in (0, 7):
        for count in (1, 2, 4, 9, 16, 64, 256, 1000):
            for pixel in range(300):
                for index in range(count if count <= 16 else 16):
                    h = (h * 31 + time_u32(pixel * 2654435761 & M32, index, count, seed)) & M32
    return h


if __name__ == "__main__":
    print("time_u32(0, 0, 1, 0) = 0x%08x" % time_u32(0, 0, 1, 0))
    print("time_u32(12345, 3, 16, 7) = 0x%08x" % time_u32(12345, 3, 16, 7))
    print("golden sweep = 0x%08x" % sweep())
