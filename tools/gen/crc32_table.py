#!/usr/bin/env python3
"""Prints the CRC-32 (IEEE 802.3, reflected polynomial 0xEDB88320) tables of src/core/crc32.c: table k maps a byte
to the CRC contribution of that byte followed by k zero bytes (k = 0 is the classic byte table), which lets the
core fold eight bytes per step ("slicing by 8")."""
POLY = 0xEDB88320
t0 = []
for n in range(256):
    c = n
    for _ in range(8):
        c = (c >> 1) ^ POLY if c & 1 else c >> 1
    t0.append(c)
tables = [t0]
for k in range(1, 8):
    prev = tables[-1]
    tables.append([(prev[n] >> 8) ^ t0[prev[n] & 0xFF] for n in range(256)])
print("static const uint32_t slice_table[8][256] = {")
for t in tables:
    print("    {")
    for i in range(0, 256, 6):
        print("        " + ", ".join("0x%08xu" % x for x in t[i:i + 6]) + ",")
    print("    },")
print("};")
