#!/usr/bin/env python3
"""Generates COUNT shaders from SEED and runs osl-difftest on them.

  run.py --difftest PATH --seed S --count N [--keep DIR]

Used by ctest (a fixed seed) and bench/difftest.sh (any number). Prints
osl-difftest's summary; on a mismatch, the failing shader is kept (in
--keep, or a temporary directory that is not deleted) for reduce.py.
"""
import argparse
import os
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import generate  # noqa: E402


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--difftest", required=True)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--count", type=int, default=200)
    ap.add_argument("--keep")
    a = ap.parse_args()
    out = a.keep or tempfile.mkdtemp(prefix="osl-difftest-")
    os.makedirs(out, exist_ok=True)
    files = []
    for s in range(a.seed, a.seed + a.count):
        path = os.path.join(out, "gen_%d.osl" % s)
        with open(path, "w") as f:
            f.write(generate.generate(s))
        files.append(path)
    r = subprocess.run([a.difftest, "--quiet"] + files, capture_output=True, text=True)
    sys.stdout.write(r.stdout)
    sys.stderr.write(r.stderr)
    if r.returncode == 0 and not a.keep:
        for path in files:
            os.remove(path)
        os.rmdir(out)
    elif r.returncode != 0:
        print("programs kept in %s" % out)
    return r.returncode


if __name__ == "__main__":
    sys.exit(main())
