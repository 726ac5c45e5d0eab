#!/usr/bin/env python3
"""Writes the seed corpus of the option parsers' fuzz target (test/fuzz/corpus/opts), in the form fuzz_opts.c
reads (the command, then its arguments, NUL-separated): every `hzrt render|show|latency` command line of
test/cli/run.sh (shell variables replaced by plain words), and one line per option of each command's help text,
with a value from the limits or words the help prints.

    python3 test/fuzz/mkseeds_opts.py HZRT [OUT_DIR]

Run it again only to change the seeds; the fuzzer does not need it (its output is committed).
"""
import hashlib
import os
import re
import shlex
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
CMDS = ("render", "show", "latency")


def write(out, args):
    data = b"\0".join(a.encode() for a in args)
    name = hashlib.sha1(data).hexdigest()[:12]
    with open(os.path.join(out, f"{args[0]}-{name}"), "wb") as f:
        f.write(data)


def from_run_sh(out):
    text = open(os.path.join(HERE, "..", "cli", "run.sh")).read().replace("\\\n", " ")
    n = 0
    for line in text.splitlines():
        m = re.search(r'"\$hzrt" (render|show|latency)\b(.*)', line)
        if not m:
            continue
        rest = m.group(2).split(" 2>")[0].split(" >")[0].split(" |")[0].split(";")[0]
        rest = re.sub(r'\$\{?\w+\}?', "out", rest)
        try:
            args = shlex.split(rest)
        except ValueError:
            continue
        write(out, [m.group(1)] + args)
        n += 1
    return n


def from_help(hzrt, out):
    n = 0
    for cmd in CMDS:
        text = subprocess.run([hzrt, cmd, "--help"], capture_output=True, text=True).stdout
        for line in text.splitlines():
            m = re.match(r"\s+(--[a-z0-9-]+)(?: ([A-Z][A-Za-z0-9:\[\]|.,_-]*))?\s+(.*)", line)
            if not m:
                continue
            opt, arg, help_ = m.groups()
            args = [cmd] + (["builtin"] if cmd != "latency" else [])
            if arg:
                lim = re.search(r"\[(-?[0-9.e+]+)\.\.(-?[0-9.e+]+)\]", help_)
                words = re.search(r"\b([a-z0-9]+(?:[,|] ?[a-z0-9:]+)+)\b", help_)
                if lim:
                    value = lim.group(2)
                elif "x" in arg.lower() and arg.upper() == "WXH":
                    value = "64x36"
                elif words:
                    value = re.split(r"[,|] ?", words.group(1))[-1]
                else:
                    value = "1"
                args += [opt, value]
            else:
                args += [opt]
            write(out, args)
            n += 1
    return n


def main():
    hzrt = sys.argv[1]
    out = sys.argv[2] if len(sys.argv) > 2 else os.path.join(HERE, "corpus", "opts")
    os.makedirs(out, exist_ok=True)
    print(f"{from_run_sh(out)} command lines from test/cli/run.sh, {from_help(hzrt, out)} from the help texts")


main()
