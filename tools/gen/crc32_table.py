#!/usr/bin/env python3
"""Prints the 256-entry CRC-32 (IEEE 802.3, reflected polynomial 0xEDB88320) table used by src/core/crc32.c."""
POLY = 0xEDB88320
table = []
for n in range(256):
    c = n
    for _ in range(8):
        c = (c >> 1) ^ POLY if c & 1 else c >> 1
    table.append(c)
for i in range(0, 256, 8):
    print("    " + ", ".join("0x%08xu" % x for x in table[i:i + 8]) + ",")
