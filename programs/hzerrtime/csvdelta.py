#!/usr/bin/env python3
"""Differences between two `make report` CSVs (build/report/errtime.csv): per scene and method, the change of
PSNR (sRGB 8-bit) and mean FLIP from A to B, and the worst of each. Usage: csvdelta.py A.csv B.csv"""
import csv
import sys


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    rows = [list(csv.DictReader(open(p, newline=""))) for p in sys.argv[1:]]
    key = lambda r: (r["scene"], r["method"], r["knob"], r["value"], r["refresh_hz"])
    after = {key(r): r for r in rows[1]}
    worst_p, worst_f = (0.0, None), (0.0, None)
    for r in rows[0]:
        s = after.get(key(r))
        if s is None:
            print("%s: only in %s" % ("/".join(key(r)), sys.argv[1]))
            continue
        dp = float(s["psnr_srgb8_db"]) - float(r["psnr_srgb8_db"])
        df = float(s["flip_mean"]) - float(r["flip_mean"])
        print("%-18s %-14s %s=%-4s  PSNR %8.4f -> %8.4f dB (%+.4f)  FLIP %.6f -> %.6f (%+.6f)" % (
            r["scene"], r["method"], r["knob"], r["value"], float(r["psnr_srgb8_db"]), float(s["psnr_srgb8_db"]),
            dp, float(r["flip_mean"]), float(s["flip_mean"]), df))
        if abs(dp) > abs(worst_p[0]):
            worst_p = (dp, key(r))
        if abs(df) > abs(worst_f[0]):
            worst_f = (df, key(r))
    print("worst PSNR change %+.4f dB (%s)" % (worst_p[0], " ".join(worst_p[1] or ())))
    print("worst FLIP change %+.6f (%s)" % (worst_f[0], " ".join(worst_f[1] or ())))


if __name__ == "__main__":
    main()
